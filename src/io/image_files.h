// The images pgt writes, each encoded by its own format's library: frame.exr by OpenEXR, the
// error maps by libpng, their legends' text by FreeType. None of them needs OpenImageIO, whose
// codecs' 260 shared libraries a process then loads only to read an image
// (heightfield/image_reader.h).
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "io/staged_files.h"

namespace pgt {

// frame.exr's compressions by name (`--exr-compression`), "auto" first: zip at level 1 where
// a row holds fewer than kPizRowValues values (width x channels), PIZ from there (the cheaper
// of the two: image_files.cpp); then "piz", "zip" and "none".
const std::vector<std::string>& exrCompressionNames();
inline constexpr size_t kPizRowValues = 40000;

// A float EXR written row band by row band into a staged stream.
class ExrWriter {
  public:
    // `compression`: one of exrCompressionNames() (else InputError); `attributes`: string
    // attributes of the header (provenance). Throws OutputError naming `name`.
    ExrWriter(StagedStream& out, const std::string& name, int width, int height,
              const std::vector<std::string>& channels, const std::string& compression,
              const std::map<std::string, std::string>& attributes = {});
    ~ExrWriter();
    ExrWriter(const ExrWriter&) = delete;
    ExrWriter& operator=(const ExrWriter&) = delete;
    // The next rows [y0, y1), each pixel's channels interleaved in the constructor's order.
    // Throws OutputError (a failed write: the stream's errno first).
    void writeRows(int y0, int y1, const float* rows);
    // Ends the file and finishes the stream (flushed to the disk). Throws OutputError.
    void close();

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// An 8-bit RGB PNG (rows top-down, 3 bytes a pixel) into `out`, which it finishes: no row
// filter, zlib level 1 (docs/outputs.md). Throws OutputError naming `name`.
void writePng(StagedStream& out, const std::string& name, int width, int height,
              const uint8_t* rgb);

// Draws `text` in white, DejaVu Sans at `pixels` pixels, its baseline at row y from column x,
// onto an RGB image of width x height (clipped to it). Nothing where the font is not
// installed (package fonts-dejavu-core).
void drawText(uint8_t* rgb, int width, int height, int x, int y, const std::string& text,
              int pixels);

}  // namespace pgt
