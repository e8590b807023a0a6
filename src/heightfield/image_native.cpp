// PNG, OpenEXR and TIFF height maps read with libpng, OpenEXR and libtiff directly
// (heightfield/image_reader.h): the formats nearly every height map comes in, without the
// image module's 260 shared libraries. What each reader leaves to the module (a layout it does
// not take) is listed beside it; the values it reads are the file's own, as the module reads
// them, except that colour beside a partial alpha is not premultiplied (docs/model.md §1).
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <png.h>
#include <strings.h>
#include <tiffio.h>

#include <algorithm>
#include <cerrno>
#include <csetjmp>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include "heightfield/image_reader.h"

namespace pgt {

namespace {

size_t bytesOf(SampleType t) {
    return t == SampleType::UInt8 ? 1 : t == SampleType::UInt16 ? 2 : 4;
}

// ---- PNG (libpng): every colour type and bit depth, expanded as the module expands them
// (palette to RGB, 1-4 bit grey to 8 bits, a tRNS chunk to alpha), 16-bit in host order.

struct PngState {
    std::FILE* file = nullptr;
    png_structp png = nullptr;
    png_infop info = nullptr;
    std::string error;
};

void pngError(png_structp png, png_const_charp message) {
    auto* s = static_cast<PngState*>(png_get_error_ptr(png));
    s->error = message ? message : "libpng error";
    std::longjmp(png_jmpbuf(png), 1);
}

void pngWarning(png_structp, png_const_charp) {}  // a decodable file's notes are not errors

// setjmp's functions hold no object with a destructor (longjmp would skip it).
bool pngReadInfo(PngState& s, ImageHeader& h) {
    if (setjmp(png_jmpbuf(s.png))) return false;
    png_init_io(s.png, s.file);
    png_read_info(s.png, s.info);
    png_set_expand(s.png);
    png_set_swap(s.png);  // PNG stores 16-bit samples big-endian; x86-64 and ARM64 are not
    png_set_interlace_handling(s.png);
    png_read_update_info(s.png, s.info);
    h.width = int(png_get_image_width(s.png, s.info));
    h.height = int(png_get_image_height(s.png, s.info));
    h.channels = int(png_get_channels(s.png, s.info));
    h.type = png_get_bit_depth(s.png, s.info) == 16 ? SampleType::UInt16 : SampleType::UInt8;
    h.sampleBytes = bytesOf(h.type);
    return true;
}

bool pngReadRows(PngState& s, png_bytep* rows) {
    if (setjmp(png_jmpbuf(s.png))) return false;
    png_read_image(s.png, rows);
    png_read_end(s.png, nullptr);
    return true;
}

class PngImage : public ImageFile {
  public:
    ~PngImage() override {
        if (s_.png) png_destroy_read_struct(&s_.png, s_.info ? &s_.info : nullptr, nullptr);
        if (s_.file) std::fclose(s_.file);
    }
    bool open(const std::string& path, std::string& why) {
        s_.file = std::fopen(path.c_str(), "rb");
        if (!s_.file) return (why = std::strerror(errno)), false;
        s_.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &s_, pngError, pngWarning);
        if (s_.png) s_.info = png_create_info_struct(s_.png);
        if (!s_.png || !s_.info) return (why = "libpng: out of memory"), false;
        if (!pngReadInfo(s_, header_)) return (why = "PNG: " + s_.error), false;
        return true;
    }
    ImageHeader header() const override { return header_; }
    bool read(void* out, std::string& why) override {
        const size_t rowBytes = size_t(header_.width) * header_.channels * header_.sampleBytes;
        std::vector<png_bytep> rows(size_t(header_.height));
        for (size_t r = 0; r < rows.size(); ++r)
            rows[r] = static_cast<png_bytep>(out) + r * rowBytes;
        if (!pngReadRows(s_, rows.data())) return (why = "PNG: " + s_.error), false;
        return true;
    }

  private:
    PngState s_;
    ImageHeader header_;
};

// ---- OpenEXR: scan-line or tiled, one part (the first), half and float channels; left to the
// module: 32-bit unsigned channels (which it reads normalised), subsampled channels, deep data.

// The order the module presents an EXR's channels in (so `"channel": N` means the same with
// either): by layer (the name up to its last dot; none first), within a layer the colour
// names first in this order (case-insensitive), then the rest by name.
int channelRank(const std::string& suffix) {
    static const char* kRanked[] = {"R",    "Red",  "G",  "Green", "B",     "Blue", "Y",
                                    "real", "imag", "A",  "Alpha", "AR",    "RA",   "AG",
                                    "GA",   "AB",   "BA", "Z",     "Depth", "Zback"};
    for (int i = 0; i < int(std::size(kRanked)); ++i)
        if (strcasecmp(suffix.c_str(), kRanked[i]) == 0) return i;
    return 10000;
}

struct ExrChannel {
    std::string name, layer, suffix;
    int rank = 0;
    explicit ExrChannel(std::string n) : name(std::move(n)) {
        const size_t dot = name.find_last_of('.');
        layer = dot == std::string::npos ? "" : name.substr(0, dot + 1);
        suffix = dot == std::string::npos ? name : name.substr(dot + 1);
        rank = channelRank(suffix);
    }
    bool operator<(const ExrChannel& o) const {
        if (layer != o.layer) return layer < o.layer;
        if (rank != o.rank) return rank < o.rank;
        return suffix < o.suffix;
    }
};

class ExrImage : public ImageFile {
  public:
    // False with `why` empty: a layout left to the module.
    bool open(const std::string& path, std::string& why) {
        try {
            file_ = std::make_unique<Imf::InputFile>(path.c_str());
            const Imf::Header& hdr = file_->header();
            if (hdr.hasType() && hdr.type().find("deep") != std::string::npos) return false;
            size_t widest = 0;
            for (auto c = hdr.channels().begin(); c != hdr.channels().end(); ++c) {
                const Imf::Channel& ch = c.channel();
                if (ch.type == Imf::UINT || ch.xSampling != 1 || ch.ySampling != 1) return false;
                widest = std::max<size_t>(widest, ch.type == Imf::HALF ? 2 : 4);
                channels_.emplace_back(c.name());
            }
            std::sort(channels_.begin(), channels_.end());
            const Imath::Box2i dw = hdr.dataWindow();
            window_ = dw;
            header_ = {dw.max.x - dw.min.x + 1, dw.max.y - dw.min.y + 1, int(channels_.size()),
                       SampleType::Float, widest};
            return !channels_.empty() || (why = "OpenEXR: no channels", false);
        } catch (const std::exception& e) {
            why = std::string("OpenEXR: ") + e.what();
            return false;
        }
    }
    ImageHeader header() const override { return header_; }
    bool read(void* out, std::string& why) override {
        try {
            const size_t px = size_t(header_.channels) * sizeof(float);
            const size_t row = px * size_t(header_.width);
            // OpenEXR addresses the slice by absolute pixel (x, y) of the data window.
            char* base = static_cast<char*>(out) - ptrdiff_t(window_.min.x) * ptrdiff_t(px) -
                         ptrdiff_t(window_.min.y) * ptrdiff_t(row);
            Imf::FrameBuffer fb;
            for (size_t c = 0; c < channels_.size(); ++c)
                fb.insert(channels_[c].name,
                          Imf::Slice(Imf::FLOAT, base + c * sizeof(float), px, row));
            file_->setFrameBuffer(fb);
            file_->readPixels(window_.min.y, window_.max.y);
            return true;
        } catch (const std::exception& e) {
            why = std::string("OpenEXR: ") + e.what();
            return false;
        }
    }

  private:
    std::unique_ptr<Imf::InputFile> file_;
    std::vector<ExrChannel> channels_;
    Imath::Box2i window_;
    ImageHeader header_;
};

// ---- TIFF (libtiff): the first directory, grey or RGB (with any extra samples), 8- or 16-bit
// unsigned or 32-bit float samples, strips or tiles, interleaved or planar, any compression
// libtiff decodes. Left to the module: palette, YCbCr, CMYK, min-is-white and other
// photometrics, other sample sizes and signed samples. libtiff's messages go to stderr, which
// the caller folds into its error.

class TiffImage : public ImageFile {
  public:
    ~TiffImage() override {
        if (tif_) TIFFClose(tif_);
    }
    // False with `why` empty: a layout left to the module.
    bool open(const std::string& path, std::string& why) {
        tif_ = TIFFOpen(path.c_str(), "r");
        if (!tif_) return (why = "libtiff cannot open the file"), false;
        uint32_t w = 0, h = 0;
        uint16_t spp = 1, bits = 1, format = SAMPLEFORMAT_UINT, photometric = 0;
        TIFFGetField(tif_, TIFFTAG_IMAGEWIDTH, &w);
        TIFFGetField(tif_, TIFFTAG_IMAGELENGTH, &h);
        TIFFGetFieldDefaulted(tif_, TIFFTAG_SAMPLESPERPIXEL, &spp);
        TIFFGetFieldDefaulted(tif_, TIFFTAG_BITSPERSAMPLE, &bits);
        TIFFGetFieldDefaulted(tif_, TIFFTAG_SAMPLEFORMAT, &format);
        TIFFGetFieldDefaulted(tif_, TIFFTAG_PLANARCONFIG, &planar_);
        if (!TIFFGetField(tif_, TIFFTAG_PHOTOMETRIC, &photometric)) return false;
        if (photometric != PHOTOMETRIC_MINISBLACK && photometric != PHOTOMETRIC_RGB) return false;
        SampleType type;
        if (format == SAMPLEFORMAT_UINT && bits == 8)
            type = SampleType::UInt8;
        else if (format == SAMPLEFORMAT_UINT && bits == 16)
            type = SampleType::UInt16;
        else if (format == SAMPLEFORMAT_IEEEFP && bits == 32)
            type = SampleType::Float;
        else
            return false;
        if (w == 0 || h == 0 || spp == 0 || w > (1u << 30) || h > (1u << 30)) return false;
        header_ = {int(w), int(h), int(spp), type, bytesOf(type)};
        return true;
    }
    ImageHeader header() const override { return header_; }
    bool read(void* out, std::string& why) override {
        const bool ok = TIFFIsTiled(tif_) ? readTiles(static_cast<uint8_t*>(out))
                                          : readStrips(static_cast<uint8_t*>(out));
        if (!ok) why = "libtiff cannot decode the image";
        return ok;
    }

  private:
    // Copies a decoded block (`bw` samples-per-pixel-wide pixels a row, `rows` rows, from
    // (x0, y0), one plane `s` or all interleaved) into the interleaved output, clipped.
    void place(const uint8_t* block, uint32_t bw, uint32_t rows, uint32_t x0, uint32_t y0,
               int plane, uint8_t* out) const {
        const size_t sb = header_.sampleBytes, nc = size_t(header_.channels);
        const size_t perPixel = plane < 0 ? nc : 1;
        const uint32_t cols = std::min<uint32_t>(bw, uint32_t(header_.width) - x0);
        rows = std::min<uint32_t>(rows, uint32_t(header_.height) - y0);
        for (uint32_t r = 0; r < rows; ++r) {
            const uint8_t* src = block + size_t(r) * bw * perPixel * sb;
            uint8_t* dst = out + ((size_t(y0) + r) * header_.width + x0) * nc * sb;
            if (plane < 0) {
                std::memcpy(dst, src, size_t(cols) * nc * sb);
                continue;
            }
            for (uint32_t x = 0; x < cols; ++x)
                std::memcpy(dst + (size_t(x) * nc + size_t(plane)) * sb, src + size_t(x) * sb, sb);
        }
    }
    int planes() const { return planar_ == PLANARCONFIG_SEPARATE ? header_.channels : 1; }
    int planeIndex(int p) const { return planar_ == PLANARCONFIG_SEPARATE ? p : -1; }

    bool readStrips(uint8_t* out) {
        uint32_t rowsPerStrip = uint32_t(header_.height);
        TIFFGetFieldDefaulted(tif_, TIFFTAG_ROWSPERSTRIP, &rowsPerStrip);
        rowsPerStrip = std::min<uint32_t>(std::max<uint32_t>(rowsPerStrip, 1), header_.height);
        std::vector<uint8_t> buf(size_t(TIFFStripSize(tif_)));
        for (int p = 0; p < planes(); ++p)
            for (uint32_t y = 0; y < uint32_t(header_.height); y += rowsPerStrip) {
                const tstrip_t strip = TIFFComputeStrip(tif_, y, uint16_t(p));
                if (TIFFReadEncodedStrip(tif_, strip, buf.data(), tmsize_t(buf.size())) < 0)
                    return false;
                place(buf.data(), uint32_t(header_.width), rowsPerStrip, 0, y, planeIndex(p), out);
            }
        return true;
    }
    bool readTiles(uint8_t* out) {
        uint32_t tw = 0, th = 0;
        TIFFGetField(tif_, TIFFTAG_TILEWIDTH, &tw);
        TIFFGetField(tif_, TIFFTAG_TILELENGTH, &th);
        if (tw == 0 || th == 0) return false;
        std::vector<uint8_t> buf(size_t(TIFFTileSize(tif_)));
        for (int p = 0; p < planes(); ++p)
            for (uint32_t y = 0; y < uint32_t(header_.height); y += th)
                for (uint32_t x = 0; x < uint32_t(header_.width); x += tw) {
                    const ttile_t tile = TIFFComputeTile(tif_, x, y, 0, uint16_t(p));
                    if (TIFFReadEncodedTile(tif_, tile, buf.data(), tmsize_t(buf.size())) < 0)
                        return false;
                    place(buf.data(), tw, th, x, y, planeIndex(p), out);
                }
        return true;
    }

    TIFF* tif_ = nullptr;
    uint16_t planar_ = PLANARCONFIG_CONTIG;
    ImageHeader header_;
};

enum class Format { Png, Exr, Tiff, Other };

Format sniff(const std::string& path) {
    unsigned char m[8] = {};
    std::ifstream in(path, std::ios::binary);
    if (!in.read(reinterpret_cast<char*>(m), sizeof m)) return Format::Other;
    if (png_sig_cmp(m, 0, 8) == 0) return Format::Png;
    if (m[0] == 0x76 && m[1] == 0x2f && m[2] == 0x31 && m[3] == 0x01) return Format::Exr;
    if ((m[0] == 'I' && m[1] == 'I' && (m[2] == 42 || m[2] == 43) && m[3] == 0) ||
        (m[0] == 'M' && m[1] == 'M' && m[2] == 0 && (m[3] == 42 || m[3] == 43)))
        return Format::Tiff;
    return Format::Other;
}

template <class Reader>
std::unique_ptr<ImageFile> tryOpen(const std::string& path, std::string& why, bool& handled) {
    auto r = std::make_unique<Reader>();
    why.clear();
    if (r->open(path, why)) return r;
    handled = !why.empty();  // an error of a file in this format, not a layout left over
    return nullptr;
}

}  // namespace

std::unique_ptr<ImageFile> openNativeImage(const std::string& path, std::string& why,
                                           bool& handled) {
    handled = true;
    switch (sniff(path)) {
        case Format::Png:  // every PNG is libpng's: a failure is this file's error
            return tryOpen<PngImage>(path, why, handled);
        case Format::Exr:
            return tryOpen<ExrImage>(path, why, handled);
        case Format::Tiff:
            return tryOpen<TiffImage>(path, why, handled);
        case Format::Other:
            break;
    }
    handled = false;
    return nullptr;
}

}  // namespace pgt
