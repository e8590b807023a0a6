// The direct PNG, OpenEXR and TIFF readers (heightfield/image_native.cpp) against two oracles:
// the values written into each file (exact), and OpenImageIO's module reading the same file
// (the same header, the same bytes), over the layouts each format's height maps come in.
#include "heightfield/image_reader.h"

#include <Imath/half.h>
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <png.h>

#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include "heightfield/heightfield.h"
#include "test_util.h"

namespace pgt {
namespace {

namespace fs = std::filesystem;

// A file's header and every sample, as one reader decodes them.
struct Decoded {
    ImageHeader header;
    std::vector<uint8_t> bytes;
    std::string why;
    bool ok = false;
};

Decoded decode(const std::string& path, ImageDecoder decoder) {
    Decoded d;
    auto in = openImageFile(path, d.why, decoder);
    if (!in) return d;
    d.header = in->header();
    const ImageHeader& h = d.header;
    const size_t size = h.type == SampleType::UInt8 ? 1 : h.type == SampleType::UInt16 ? 2 : 4;
    d.bytes.resize(size_t(h.width) * h.height * h.channels * size);
    d.ok = in->read(d.bytes.data(), d.why);
    return d;
}

// Sample k of a W x H x C image: distinct, spread over the type's range.
double sampleValue(size_t k, OIIO::TypeDesc type) {
    const double f = double((k * 7919) % 1000) / 999.0;
    if (type == OIIO::TypeDesc::UINT8) return std::round(f * 255);
    if (type == OIIO::TypeDesc::UINT16) return std::round(f * 65535);
    if (type == OIIO::TypeDesc::HALF) return double(Imath::half(float(f * 3 - 1)));
    return float(f * 3 - 1);
}

// Writes `path` through OpenImageIO with `spec` (and its attributes) and returns the samples
// written, interleaved, rows top-down, as doubles.
std::vector<double> writeImage(const std::string& path, OIIO::ImageSpec spec) {
    const size_t n = size_t(spec.width) * spec.height * spec.nchannels;
    std::vector<double> values(n);
    for (size_t k = 0; k < n; ++k) values[k] = sampleValue(k, spec.format);
    std::vector<float> asFloat(values.begin(), values.end());
    for (float& v : asFloat)
        if (spec.format == OIIO::TypeDesc::UINT8)
            v /= 255.0f;
        else if (spec.format == OIIO::TypeDesc::UINT16)
            v /= 65535.0f;
    auto out = OIIO::ImageOutput::create(path);
    EXPECT_TRUE(out && out->open(path, spec)) << path << ": " << OIIO::geterror();
    EXPECT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, asFloat.data())) << out->geterror();
    out->close();
    return values;
}

std::vector<double> asDoubles(const Decoded& d) {
    const size_t n = size_t(d.header.width) * d.header.height * d.header.channels;
    std::vector<double> v(n);
    for (size_t k = 0; k < n; ++k) {
        if (d.header.type == SampleType::UInt8) v[k] = d.bytes[k];
        if (d.header.type == SampleType::UInt16) {
            uint16_t s;
            std::memcpy(&s, &d.bytes[2 * k], 2);
            v[k] = s;
        }
        if (d.header.type == SampleType::Float) {
            float s;
            std::memcpy(&s, &d.bytes[4 * k], 4);
            v[k] = s;
        }
    }
    return v;
}

void expectSameAsModule(const std::string& path, const Decoded& direct) {
    const Decoded module = decode(path, ImageDecoder::Module);
    ASSERT_TRUE(module.ok) << module.why;
    EXPECT_EQ(direct.header.width, module.header.width) << path;
    EXPECT_EQ(direct.header.height, module.header.height) << path;
    EXPECT_EQ(direct.header.channels, module.header.channels) << path;
    EXPECT_EQ(direct.header.type, module.header.type) << path;
    EXPECT_EQ(direct.header.sampleBytes, module.header.sampleBytes) << path;
    EXPECT_TRUE(direct.bytes == module.bytes) << path << ": the samples differ";
}

struct Layout {
    std::string name;  // the file's name: its extension picks the writer
    int width, height, channels;
    OIIO::TypeDesc type;
    std::function<void(OIIO::ImageSpec&)> attributes = [](OIIO::ImageSpec&) {};
};

std::vector<Layout> layouts() {
    using T = OIIO::TypeDesc;
    auto set = [](const char* key, const char* value) {
        return [=](OIIO::ImageSpec& s) { s.attribute(key, value); };
    };
    return {
        {"grey8.png", 13, 7, 1, T::UINT8},
        {"grey16.png", 9, 11, 1, T::UINT16},
        {"rgb8.png", 5, 6, 3, T::UINT8},
        {"rgb16.png", 6, 5, 3, T::UINT16},
        {"grey_half.exr", 17, 9, 1, T::HALF},
        {"rgb_float.exr", 8, 8, 3, T::FLOAT},
        {"piz_half.exr", 33, 21, 2, T::HALF, set("compression", "piz")},
        {"tiled.exr", 37, 19, 1, T::FLOAT,
         [](OIIO::ImageSpec& s) { s.tile_width = s.tile_height = 16; }},
        {"named.exr", 7, 5, 6, T::HALF,
         [](OIIO::ImageSpec& s) {
             s.channelnames = {"height", "Z", "B", "A", "G", "R"};
             s.alpha_channel = -1;
             s.z_channel = -1;
         }},
        {"layers.exr", 4, 6, 4, T::FLOAT,
         [](OIIO::ImageSpec& s) {
             s.channelnames = {"rough.Y", "depth", "disp.height", "disp.R"};
             s.alpha_channel = -1;
         }},
        {"offset.exr", 10, 4, 1, T::FLOAT,
         [](OIIO::ImageSpec& s) {
             s.x = 3;
             s.y = -2;
         }},
        {"grey8.tif", 13, 7, 1, T::UINT8},
        {"rgb16_lzw.tif", 10, 9, 3, T::UINT16, set("compression", "lzw")},
        {"float_zip.tif", 12, 12, 1, T::FLOAT, set("compression", "zip")},
        {"strips.tif", 11, 23, 2, T::UINT16,
         [](OIIO::ImageSpec& s) { s.attribute("tiff:RowsPerStrip", 4); }},
        {"planar.tif", 9, 10, 3, T::UINT8, set("planarconfig", "separate")},
        {"tiled.tif", 40, 35, 1, T::UINT16,
         [](OIIO::ImageSpec& s) { s.tile_width = s.tile_height = 16; }},
        {"tiled_planar.tif", 20, 18, 3, T::FLOAT,
         [](OIIO::ImageSpec& s) {
             s.tile_width = s.tile_height = 16;
             s.attribute("planarconfig", "separate");
         }},
    };
}

// Every layout: the direct reader returns the values written, exactly, and what the module
// returns, byte for byte.
TEST(ImageReaders, DirectReadersReturnTheWrittenValuesAndTheModulesBytes) {
    const fs::path dir = test::tempDir("image_readers");
    for (const Layout& l : layouts()) {
        const std::string path = (dir / l.name).string();
        OIIO::ImageSpec spec(l.width, l.height, l.channels, l.type);
        l.attributes(spec);
        std::vector<double> written = writeImage(path, spec);
        const Decoded direct = decode(path, ImageDecoder::Direct);
        ASSERT_TRUE(direct.ok) << l.name << ": " << direct.why;
        if (l.name != "named.exr" && l.name != "layers.exr") {  // reordered: compared below
            EXPECT_EQ(asDoubles(direct), written) << l.name;
        }
        expectSameAsModule(path, direct);
    }
    fs::remove_all(dir);
}

// An EXR's channels come in the module's order: colour names first, by layer.
TEST(ImageReaders, ExrChannelsComeInTheModulesOrder) {
    const fs::path dir = test::tempDir("image_exr_order");
    const std::string path = (dir / "named.exr").string();
    OIIO::ImageSpec spec(2, 1, 6, OIIO::TypeDesc::FLOAT);
    spec.channelnames = {"height", "Z", "B", "A", "G", "R"};
    spec.alpha_channel = spec.z_channel = -1;
    std::vector<float> px = {1, 2, 3, 4, 5, 6, 11, 12, 13, 14, 15, 16};
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out->open(path, spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data()));
    out->close();
    const Decoded d = decode(path, ImageDecoder::Direct);
    ASSERT_TRUE(d.ok) << d.why;
    // R, G, B, A, Z, height.
    EXPECT_EQ(asDoubles(d), (std::vector<double>{6, 5, 3, 4, 2, 1, 16, 15, 13, 14, 12, 11}));
    fs::remove_all(dir);
}

// libpng's own writer for what OpenImageIO does not write: palette, 2-bit grey, a tRNS chunk,
// Adam7 interlacing. `rows` holds one packed row after another.
void writePng(const std::string& path, int w, int h, int depth, int colour, bool interlace,
              const std::vector<uint8_t>& rows, const std::vector<png_color>& palette = {},
              const std::vector<uint8_t>& trns = {}) {
    std::FILE* f = std::fopen(path.c_str(), "wb");
    ASSERT_NE(f, nullptr);
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png_create_info_struct(png);
    png_init_io(png, f);
    png_set_IHDR(png, info, png_uint_32(w), png_uint_32(h), depth, colour,
                 interlace ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    if (!palette.empty()) png_set_PLTE(png, info, palette.data(), int(palette.size()));
    if (!trns.empty()) png_set_tRNS(png, info, trns.data(), int(trns.size()), nullptr);
    png_write_info(png, info);
    const size_t stride = rows.size() / size_t(h);
    std::vector<png_bytep> ptrs(static_cast<size_t>(h));
    for (int r = 0; r < h; ++r) ptrs[size_t(r)] = const_cast<uint8_t*>(&rows[size_t(r) * stride]);
    png_write_image(png, ptrs.data());
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    std::fclose(f);
}

TEST(ImageReaders, PngPalettesLowBitDepthsTransparencyAndInterlacingMatchTheModule) {
    const fs::path dir = test::tempDir("image_png_kinds");
    const int w = 10, h = 9;
    std::vector<uint8_t> index(size_t(w) * h);
    for (size_t k = 0; k < index.size(); ++k) index[k] = uint8_t((k * 5) % 4);
    const std::vector<png_color> palette = {{0, 0, 0}, {255, 10, 20}, {30, 200, 40}, {7, 8, 250}};
    std::vector<uint8_t> grey2(size_t((w * 2 + 7) / 8) * h, 0);  // 2-bit grey, packed
    for (int r = 0; r < h; ++r)
        for (int x = 0; x < w; ++x)
            grey2[size_t(r) * ((w * 2 + 7) / 8) + size_t(x / 4)] |=
                uint8_t(((r + x) % 4) << (6 - 2 * (x % 4)));
    std::vector<uint8_t> grey16(size_t(w) * h * 2);
    for (size_t k = 0; k < grey16.size(); ++k) grey16[k] = uint8_t(k * 37);
    struct Case {
        std::string name;
        std::function<void(const std::string&)> write;
        int channels;
    };
    const std::vector<Case> cases = {
        {"palette.png",
         [&](const std::string& p) {
             writePng(p, w, h, 8, PNG_COLOR_TYPE_PALETTE, false, index, palette);
         },
         3},
        {"palette_trns.png",
         [&](const std::string& p) {
             writePng(p, w, h, 8, PNG_COLOR_TYPE_PALETTE, false, index, palette,
                      {255, 255, 255, 255});
         },
         4},
        {"grey2.png",
         [&](const std::string& p) { writePng(p, w, h, 2, PNG_COLOR_TYPE_GRAY, false, grey2); }, 1},
        {"grey16_adam7.png",
         [&](const std::string& p) { writePng(p, w, h, 16, PNG_COLOR_TYPE_GRAY, true, grey16); },
         1},
    };
    for (const Case& c : cases) {
        const std::string path = (dir / c.name).string();
        c.write(path);
        const Decoded direct = decode(path, ImageDecoder::Direct);
        ASSERT_TRUE(direct.ok) << c.name << ": " << direct.why;
        EXPECT_EQ(direct.header.channels, c.channels) << c.name;
        expectSameAsModule(path, direct);
    }
    // Closed forms: 2-bit grey g reads as g * 85; palette entry 1 as (255, 10, 20).
    const Decoded g = decode((dir / "grey2.png").string(), ImageDecoder::Direct);
    EXPECT_EQ(g.bytes[1], uint8_t(1 * 85));
    const Decoded p = decode((dir / "palette.png").string(), ImageDecoder::Direct);
    EXPECT_EQ(p.bytes[3 * 1 + 0], 255);  // pixel 1: index (1 * 5) % 4 = 1
    EXPECT_EQ(p.bytes[3 * 1 + 2], 20);
    fs::remove_all(dir);
}

// Colour beside a partial alpha is the file's own value (docs/model.md §1); OpenImageIO
// premultiplies it by the alpha, so the two readers part there, and only there.
TEST(ImageReaders, ColourBesideAPartialAlphaIsReadAsStored) {
    const fs::path dir = test::tempDir("image_alpha");
    const std::string path = (dir / "rgba.png").string();
    std::vector<uint8_t> px = {200, 100, 50, 128, 200, 100, 50, 255};  // 2 x 1 RGBA
    auto out = OIIO::ImageOutput::create(path);
    OIIO::ImageSpec spec(2, 1, 4, OIIO::TypeDesc::UINT8);
    spec.attribute("oiio:UnassociatedAlpha", 1);  // write the values as given
    ASSERT_TRUE(out->open(path, spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, px.data()));
    out->close();
    const Decoded direct = decode(path, ImageDecoder::Direct);
    ASSERT_TRUE(direct.ok) << direct.why;
    EXPECT_EQ(direct.bytes, px);
    const Decoded module = decode(path, ImageDecoder::Module);
    ASSERT_TRUE(module.ok) << module.why;
    EXPECT_NE(module.bytes[0], px[0]);  // premultiplied where alpha is 128
    EXPECT_EQ(std::vector<uint8_t>(module.bytes.begin() + 3, module.bytes.end()),
              std::vector<uint8_t>(px.begin() + 3, px.end()));  // its alpha, and the opaque pixel
    fs::remove_all(dir);
}

// Layouts the direct readers leave to the module: the module reads them (Any), Direct says so.
TEST(ImageReaders, LayoutsLeftToTheModuleAreReadByIt) {
    const fs::path dir = test::tempDir("image_left");
    for (const char* name : {"uint32.tif", "int16.tif", "uint32.exr", "grey.pgm"}) {
        const std::string path = (dir / name).string();
        const bool exr = std::string(name).find(".exr") != std::string::npos;
        const bool signed16 = std::string(name) == "int16.tif";
        OIIO::ImageSpec spec(6, 5, 1,
                             signed16                          ? OIIO::TypeDesc::INT16
                             : std::string(name) == "grey.pgm" ? OIIO::TypeDesc::UINT8
                                                               : OIIO::TypeDesc::UINT32);
        if (exr) spec.channelnames = {"id"};
        writeImage(path, spec);
        const Decoded direct = decode(path, ImageDecoder::Direct);
        EXPECT_FALSE(direct.ok) << name;
        EXPECT_NE(direct.why.find("image module"), std::string::npos) << name << ": " << direct.why;
        const Decoded any = decode(path, ImageDecoder::Any),
                      module = decode(path, ImageDecoder::Module);
        ASSERT_TRUE(any.ok && module.ok) << name << ": " << any.why << module.why;
        EXPECT_EQ(any.bytes, module.bytes) << name;
    }
    fs::remove_all(dir);
}

// A file of the direct readers' formats that is cut short or corrupt: an error naming the
// format, never a crash; the loader turns it into one line naming the scene's field.
TEST(ImageReaders, TruncatedFilesAreErrors) {
    const fs::path dir = test::tempDir("image_cut");
    for (const char* name : {"cut.png", "cut.exr", "cut.tif"}) {
        const std::string path = (dir / name).string();
        OIIO::ImageSpec spec(64, 64, 1, OIIO::TypeDesc::UINT16);
        if (std::string(name) == "cut.exr") spec.set_format(OIIO::TypeDesc::HALF);
        spec.attribute("compression", std::string(name) == "cut.tif" ? "lzw" : "zip");
        writeImage(path, spec);
        fs::resize_file(path, fs::file_size(path) * 2 / 3);
        try {
            loadHeightImage(path, 0, "scene.json", "heightmap", false);
            ADD_FAILURE() << name << ": no error";
        } catch (const InputError& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find("heightmap.file"), std::string::npos) << what;
            EXPECT_NE(what.find(name), std::string::npos) << what;
            EXPECT_EQ(what.find('\n'), std::string::npos) << what;
        }
    }
    fs::remove_all(dir);
}

}  // namespace
}  // namespace pgt
