// frame.exr through OpenEXR, the error maps through libpng and FreeType
// (io/image_files.h).
#include "io/image_files.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfThreading.h>
#include <ft2build.h>
#include <png.h>
#include FT_FREETYPE_H

#include <algorithm>
#include <csetjmp>
#include <filesystem>
#include <mutex>
#include <thread>

#include "core/error.h"

namespace pgt {

namespace {

// OpenEXR's output stream over a staged file: positioned writes, as the file's offset table
// is written last at its start.
class StagedOStream : public Imf::OStream {
  public:
    StagedOStream(StagedStream& out, const std::string& name)
        : Imf::OStream(name.c_str()), out_(out) {}
    void write(const char c[], int n) override {
        if (out_.pwrite(c, size_t(n), int64_t(pos_)) != size_t(n))
            throw std::runtime_error("short write");
        pos_ += uint64_t(n);
    }
    uint64_t tellp() override { return pos_; }
    void seekp(uint64_t pos) override { pos_ = pos; }

  private:
    StagedStream& out_;
    uint64_t pos_ = 0;
};

// "auto": PIZ builds its Huffman and lookup tables (65,536 entries each) once a block of 32
// rows: wide rows share that cost, narrow ones pay it per pixel. Measured on pgt's frames
// (docs/performance.md, 2 threads): at 512^2 x 19 channels zip level 1 took 79 ms against
// PIZ's 123 and wrote 5.1 MB against 6.6; at 1536^2 x 29, PIZ 1.19 s against 1.32; at
// 2048^2 x 29, PIZ 1.96 s against 2.33. Both are lossless.
struct NamedCompression {
    const char* name;
    Imf::Compression compression;
    int zipLevel;  // 0: OpenEXR's default
};
constexpr NamedCompression kCompressions[] = {{"auto", Imf::ZIP_COMPRESSION, 1},
                                              {"piz", Imf::PIZ_COMPRESSION, 0},
                                              {"zip", Imf::ZIP_COMPRESSION, 0},
                                              {"none", Imf::NO_COMPRESSION, 0}};

void setCompression(Imf::Header& header, const std::string& name, size_t rowValues) {
    for (const NamedCompression& c : kCompressions) {
        if (name != c.name) continue;
        const bool wide = name == "auto" && rowValues >= kPizRowValues;
        header.compression() = wide ? Imf::PIZ_COMPRESSION : c.compression;
        if (!wide && c.zipLevel) header.zipCompressionLevel() = c.zipLevel;
        return;
    }
    std::string names;
    for (const std::string& n : exrCompressionNames()) names += (names.empty() ? "" : ", ") + n;
    throw InputError("command line", "--exr-compression", name, "expected one of " + names);
}

}  // namespace

const std::vector<std::string>& exrCompressionNames() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> out;
        for (const NamedCompression& c : kCompressions) out.push_back(c.name);
        return out;
    }();
    return names;
}

struct ExrWriter::Impl {
    StagedStream& out;
    std::string name;
    int width;
    std::vector<std::string> channels;
    StagedOStream stream;
    std::unique_ptr<Imf::OutputFile> file;

    // An encoder's exception as pgt's error: the stream's own failure (its errno) first.
    [[noreturn]] void fail(const std::exception& e) {
        file.reset();
        out.finish();
        throw OutputError("cannot encode " + name + ": " + e.what());
    }
};

ExrWriter::ExrWriter(StagedStream& out, const std::string& name, int width, int height,
                     const std::vector<std::string>& channels, const std::string& compression,
                     const std::map<std::string, std::string>& attributes)
    : impl_(new Impl{out, name, width, channels, StagedOStream(out, name), nullptr}) {
    // The encoder compresses a call's chunks on OpenEXR's threads, one a core.
    static std::once_flag threads;
    std::call_once(threads, [] {
        Imf::setGlobalThreadCount(int(std::max(1u, std::thread::hardware_concurrency())));
    });
    Imf::Header header(width, height);
    setCompression(header, compression, size_t(width) * channels.size());
    for (const std::string& c : channels) header.channels().insert(c, Imf::Channel(Imf::FLOAT));
    for (const auto& [key, value] : attributes) header.insert(key, Imf::StringAttribute(value));
    try {
        impl_->file = std::make_unique<Imf::OutputFile>(impl_->stream, header);
    } catch (const std::exception& e) {
        impl_->fail(e);
    }
}

ExrWriter::~ExrWriter() = default;

void ExrWriter::writeRows(int y0, int y1, const float* rows) {
    Impl& m = *impl_;
    const size_t nc = m.channels.size(), xStride = nc * sizeof(float),
                 yStride = size_t(m.width) * xStride;
    // OpenEXR addresses pixel (x, y) at base + x xStride + y yStride: the band's base lies
    // y0 rows before its first.
    const char* base = reinterpret_cast<const char*>(rows) - ptrdiff_t(y0) * ptrdiff_t(yStride);
    Imf::FrameBuffer fb;
    for (size_t c = 0; c < nc; ++c)
        fb.insert(m.channels[c], Imf::Slice(Imf::FLOAT, const_cast<char*>(base) + c * sizeof(float),
                                            xStride, yStride));
    try {
        m.file->setFrameBuffer(fb);
        m.file->writePixels(y1 - y0);
    } catch (const std::exception& e) {
        m.fail(e);
    }
}

void ExrWriter::close() {
    impl_->file.reset();  // writes the offset table
    impl_->out.finish();
}

namespace {

// libpng reports errors by longjmp: its calls sit in a function of plain locals.
struct PngSink {
    StagedStream* out;
    char why[200];
};

void pngWrite(png_structp png, png_bytep data, size_t n) {
    auto* sink = static_cast<PngSink*>(png_get_io_ptr(png));
    if (sink->out->write(data, n) != n) png_error(png, "short write");
}

void pngError(png_structp png, png_const_charp message) {
    auto* sink = static_cast<PngSink*>(png_get_error_ptr(png));
    std::snprintf(sink->why, sizeof sink->why, "%s", message);
    png_longjmp(png, 1);
}

void pngWarning(png_structp, png_const_charp) {}

void pngFlush(png_structp) {}  // the staged stream flushes when it is finished

bool encodePng(PngSink& sink, int width, int height, const uint8_t* rgb) {
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &sink, pngError, pngWarning);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    if (!info) {
        png_destroy_write_struct(&png, nullptr);
        std::snprintf(sink.why, sizeof sink.why, "out of memory");
        return false;
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        return false;
    }
    png_set_write_fn(png, &sink, pngWrite, pngFlush);
    png_set_IHDR(png, info, png_uint_32(width), png_uint_32(height), 8, PNG_COLOR_TYPE_RGB,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    // No row filter, zlib level 1: measured on the default scene's 2048^2 maps of none,
    // parallax and pom, 0.59 s of encoding against libpng's defaults' 1.40 s, for 7 % more
    // bytes.
    png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_NONE);
    png_set_compression_level(png, 1);
    png_write_info(png, info);
    for (int y = 0; y < height; ++y) png_write_row(png, rgb + size_t(y) * size_t(width) * 3);
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    return true;
}

}  // namespace

void writePng(StagedStream& out, const std::string& name, int width, int height,
              const uint8_t* rgb) {
    PngSink sink{&out, {}};
    const bool ok = encodePng(sink, width, height, rgb);
    out.finish();  // a failed write is reported by its errno first
    if (!ok) throw OutputError("cannot encode " + name + ": " + sink.why);
}

namespace {

// DejaVu Sans where Debian's fonts-dejavu-core (and other layouts) put it; empty if absent.
std::string dejaVuSans() {
    for (const char* p :
         {"/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf", "/usr/share/fonts/TTF/DejaVuSans.ttf",
          "/usr/share/fonts/dejavu/DejaVuSans.ttf"}) {
        std::error_code ec;
        if (std::filesystem::is_regular_file(p, ec)) return p;
    }
    return {};
}

}  // namespace

void drawText(uint8_t* rgb, int width, int height, int x, int y, const std::string& text,
              int pixels) {
    static const std::string font = dejaVuSans();
    if (font.empty()) return;
    FT_Library library = nullptr;
    if (FT_Init_FreeType(&library)) return;
    FT_Face face = nullptr;
    if (!FT_New_Face(library, font.c_str(), 0, &face) &&
        !FT_Set_Pixel_Sizes(face, 0, FT_UInt(pixels))) {
        int pen = x;
        for (unsigned char ch : text) {
            if (FT_Load_Char(face, ch, FT_LOAD_RENDER)) continue;
            const FT_GlyphSlot g = face->glyph;
            const FT_Bitmap& b = g->bitmap;
            if (b.pixel_mode != FT_PIXEL_MODE_GRAY || b.pitch < 0) continue;  // 8-bit, top-down
            for (int r = 0; r < int(b.rows); ++r)
                for (int c = 0; c < int(b.width); ++c) {
                    const int px = pen + g->bitmap_left + c, py = y - g->bitmap_top + r;
                    if (px < 0 || py < 0 || px >= width || py >= height) continue;
                    const int alpha = b.buffer[r * b.pitch + c];  // white over the canvas
                    uint8_t* p = rgb + (size_t(py) * size_t(width) + size_t(px)) * 3;
                    for (int k = 0; k < 3; ++k) p[k] = uint8_t(p[k] + (255 - p[k]) * alpha / 255);
                }
            pen += int(g->advance.x >> 6);
        }
    }
    if (face) FT_Done_Face(face);
    FT_Done_FreeType(library);
}

}  // namespace pgt
