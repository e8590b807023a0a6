// Reading a height map's image file. PNG, OpenEXR and TIFF are read by libpng, OpenEXR and
// libtiff directly (heightfield/image_native.cpp); any other format, or a layout of those three
// the direct readers leave out, by OpenImageIO. OpenImageIO and the 260 shared libraries of
// its codecs live in a module of their own, pgt_image.so, loaded the first time such an image
// is read: a process that reads none does not pay the dynamic loader's 0.2 s for them
// (docs/performance.md).
#pragma once

#include <cstddef>
#include <memory>
#include <string>

namespace pgt {

// How a file's samples are stored (what decoding reads them as).
enum class SampleType { UInt8, UInt16, Float };

struct ImageHeader {
    int width = 0, height = 0, channels = 0;
    SampleType type = SampleType::Float;
    size_t sampleBytes = 4;  // in the file's own type (what decoding holds beside the doubles)
};

// An image file opened for reading.
class ImageFile {
  public:
    virtual ~ImageFile() = default;
    virtual ImageHeader header() const = 0;
    // Every channel of every pixel, rows top-down, as header().type (uint8_t, uint16_t or
    // float) into `out`; false with the decoder's error in `why`.
    virtual bool read(void* out, std::string& why) = 0;
};

// Which readers openImageFile may use: both (the direct ones first), or one of them alone
// (the tests compare them file by file).
enum class ImageDecoder { Any, Direct, Module };

// Opens `path`: null with the decoder's error in `why` when it cannot. Throws InputError
// naming what was searched when the image module is needed and not found beside the binary
// (or at $PGT_IMAGE_MODULE). With ImageDecoder::Direct, a file the direct readers leave to the
// module is null with `why` saying so.
std::unique_ptr<ImageFile> openImageFile(const std::string& path, std::string& why,
                                         ImageDecoder decoder = ImageDecoder::Any);

// The direct readers: a PNG, OpenEXR or TIFF file they take, or null: with `handled` true
// and `why` when the file is of theirs and cannot be read, with `handled` false when the
// module is to read it.
std::unique_ptr<ImageFile> openNativeImage(const std::string& path, std::string& why,
                                           bool& handled);

// What the module exports (extern "C"): a new ImageFile or null with `why`.
using OpenImageFn = ImageFile* (*)(const char* path, std::string* why);
inline constexpr const char* kOpenImageSymbol = "pgt_open_image";

}  // namespace pgt
