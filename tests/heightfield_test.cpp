// Height fields: docs/model.md §1 conventions (texel centres, v up), loading, derived maps.
#include "heightfield/heightfield.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include "core/error.h"
#include "test_util.h"

namespace pgt {
namespace {

using test::makeTexture;

TEST(Sampler, ReturnsTexelValuesAtTexelCentres) {
    Texture t = makeTexture(7, 5, [](int i, int j) { return 0.1 * i + 0.01 * j; });
    for (int j = 0; j < 5; ++j)
        for (int i = 0; i < 7; ++i) {
            Vec2d uv((i + 0.5) / 7, (j + 0.5) / 5);
            EXPECT_NEAR(sampleBilinear<double>(t, uv), t.texel(i, j), 1e-7)
                << "texel " << i << "," << j;
        }
}

TEST(Sampler, RepeatWrapsAndClampHoldsTheEdge) {
    Texture t = makeTexture(4, 4, [](int i, int) { return i == 0 ? 1.0 : (i == 3 ? 0.0 : 0.5); });
    // u = 0 lies halfway between the centres of the last and first columns.
    EXPECT_NEAR(sampleBilinear<double>(t, Vec2d(0.0, 0.5)), 0.5, 1e-12);
    t.address = Address::Clamp;
    EXPECT_NEAR(sampleBilinear<double>(t, Vec2d(0.0, 0.5)), 1.0, 1e-12);
    EXPECT_NEAR(sampleBilinear<double>(t, Vec2d(-3.0, 0.5)), 1.0, 1e-12);
    EXPECT_NEAR(sampleBilinear<double>(t, Vec2d(1.0, 0.5)), 0.0, 1e-12);
}

TEST(Sampler, NonFiniteAndHugeCoordinatesAreSafe) {
    Texture t = makeTexture(4, 4, [](int i, int j) { return 0.25 * (i + j) / 2; });
    EXPECT_TRUE(std::isnan(sampleBilinear<float>(t, Vec2f(NAN, 0.5f))));
    EXPECT_TRUE(std::isnan(sampleBilinear<float>(t, Vec2f(0.5f, INFINITY))));
    float v = sampleBilinear<float>(t, Vec2f(3e30f, -7e25f));
    EXPECT_TRUE(std::isfinite(v));
}

// Writes a W x H single-channel 8-bit PNG whose FILE row r (top-down) and column c is bright.
std::string writeSpikePng(const std::filesystem::path& dir, int w, int h, int col, int fileRow) {
    std::vector<uint8_t> px(size_t(w) * h, 0);
    px[size_t(fileRow) * w + col] = 255;
    std::string path = (dir / "spike.png").string();
    auto out = OIIO::ImageOutput::create(path);
    OIIO::ImageSpec spec(w, h, 1, OIIO::TypeDesc::UINT8);
    EXPECT_TRUE(out->open(path, spec));
    EXPECT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, px.data()));
    out->close();
    return path;
}

// docs/model.md §1: v = 0 is the bottom row of the picture (the LAST row in the file); texel
// (i, j) from the bottom has its centre at ((i + 0.5)/W, (j + 0.5)/H).
TEST(Conventions, BrightTexelIsFoundAtTheModelUv) {
    auto dir = test::tempDir("spike");
    const int w = 16, h = 8, col = 3, fileRow = 1;  // second row from the top
    Texture t = loadHeightImage(writeSpikePng(dir, w, h, col, fileRow), 0, "scene.json",
                                "heightmap", false);
    const int j = h - 1 - fileRow;  // = 6: row counted from the bottom
    EXPECT_EQ(t.texel(col, j), 1.0f);
    Vec2d uv((col + 0.5) / w, (j + 0.5) / h);
    EXPECT_DOUBLE_EQ(sampleBilinear<double>(t, uv), 1.0) << "uv " << uv.x << "," << uv.y;
    // The maximum of the continuous field is there and nowhere else on a fine scan.
    double best = -1;
    Vec2d at(0);
    for (int y = 0; y < 400; ++y)
        for (int x = 0; x < 400; ++x) {
            Vec2d p((x + 0.5) / 400, (y + 0.5) / 400);
            double v = sampleBilinear<double>(t, p);
            if (v > best) best = v, at = p;
        }
    EXPECT_NEAR(at.x, uv.x, 1.0 / 400);
    EXPECT_NEAR(at.y, uv.y, 1.0 / 400);
    std::filesystem::remove_all(dir);
}

TEST(Loading, NormalisesEightAndSixteenBit) {
    auto dir = test::tempDir("bits");
    std::string p8 = (dir / "a.png").string(), p16 = (dir / "b.png").string();
    {
        uint8_t v[2] = {128, 255};
        auto out = OIIO::ImageOutput::create(p8);
        ASSERT_TRUE(out->open(p8, OIIO::ImageSpec(2, 1, 1, OIIO::TypeDesc::UINT8)));
        ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, v));
        out->close();
    }
    {
        uint16_t v[2] = {40000, 65535};
        auto out = OIIO::ImageOutput::create(p16);
        ASSERT_TRUE(out->open(p16, OIIO::ImageSpec(2, 1, 1, OIIO::TypeDesc::UINT16)));
        ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT16, v));
        out->close();
    }
    Texture a = loadHeightImage(p8, 0, "s", "heightmap", false);
    Texture b = loadHeightImage(p16, 0, "s", "heightmap", false);
    EXPECT_EQ(a.texel(0, 0), float(128 / 255.0));
    EXPECT_EQ(b.texel(0, 0), float(40000 / 65535.0));
    EXPECT_EQ(b.texel(1, 0), 1.0f);
    std::filesystem::remove_all(dir);
}

TEST(Loading, RejectsNonFiniteTexelWithItsPosition) {
    auto dir = test::tempDir("nan");
    std::string p = (dir / "bad.exr").string();
    float v[6] = {0.1f, 0.2f, 0.3f, 0.4f, NAN, 0.6f};  // 3 x 2, NaN at column 1, file row 1
    auto out = OIIO::ImageOutput::create(p);
    ASSERT_TRUE(out->open(p, OIIO::ImageSpec(3, 2, 1, OIIO::TypeDesc::FLOAT)));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, v));
    out->close();
    try {
        loadHeightImage(p, 0, "scene.json", "heightmap", false);
        FAIL() << "expected InputError";
    } catch (const InputError& e) {
        std::string what = e.what();
        EXPECT_NE(what.find("scene.json"), std::string::npos) << what;
        EXPECT_NE(what.find("heightmap.file"), std::string::npos) << what;
        EXPECT_NE(what.find("column 1, row 1"), std::string::npos) << what;
    }
    std::filesystem::remove_all(dir);
}

TEST(Loading, AmbiguousColourImageNeedsAChannel) {
    auto dir = test::tempDir("rgb");
    std::string p = (dir / "rgb.png").string();
    uint8_t v[6] = {10, 20, 30, 10, 20, 30};
    auto out = OIIO::ImageOutput::create(p);
    ASSERT_TRUE(out->open(p, OIIO::ImageSpec(2, 1, 3, OIIO::TypeDesc::UINT8)));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, v));
    out->close();
    EXPECT_THROW(loadHeightImage(p, 0, "s", "heightmap", false), InputError);
    Texture g = loadHeightImage(p, 1, "s", "heightmap", true);
    EXPECT_EQ(g.texel(0, 0), float(20 / 255.0));
    EXPECT_THROW(loadHeightImage(p, 3, "s", "heightmap", true), InputError);
    EXPECT_THROW(loadHeightImage((dir / "missing.png").string(), 0, "s", "heightmap", false),
                 InputError);
    std::filesystem::remove_all(dir);
}

// Lengyel FGED 2 Eq. 7.41-7.43 on a ramp h = a*u: interior slope d_x = s*W/2 * 2a/W = s*a.
TEST(DerivedMaps, NormalOfARampIsClosedForm) {
    const int w = 32, h = 16;
    const double a = 0.5, s = 0.08, b = -0.04;
    Texture t = makeTexture(w, h, [&](int i, int) { return a * (i + 0.5) / w; });
    DerivedMaps m = makeDerivedMaps(t, s, b);
    double len = std::sqrt(s * a * s * a + 1);
    for (int i = 1; i < w - 1; ++i) {
        EXPECT_NEAR(m.normal.texel(i, 5, 0), -s * a / len, 1e-6) << "column " << i;
        EXPECT_NEAR(m.normal.texel(i, 5, 1), 0.0, 1e-7);
        EXPECT_NEAR(m.normal.texel(i, 5, 2), 1 / len, 1e-6);
        EXPECT_NEAR(m.parallax.texel(i, 5), (s * t.texel(i, 5) + b) / len, 1e-6);
    }
}

TEST(Procedural, RampIsLinearAtTexelCentres) {
    Texture t = makeProceduralHeight(
        nlohmann::json::parse(
            R"({"procedural":"ramp","size":[8,4],"slope":[0.5,0.25],"offset":0.1})"),
        "s", "heightmap");
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 8; ++i)
            EXPECT_NEAR(t.texel(i, j), 0.1 + 0.5 * (i + 0.5) / 8 + 0.25 * (j + 0.5) / 4, 1e-7);
}

TEST(Procedural, MisspeltGeneratorIsRejectedWithASuggestion) {
    try {
        makeProceduralHeight(nlohmann::json::parse(R"({"procedural":"brikcs"})"), "s.json",
                             "heightmap");
        FAIL();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("did you mean \"bricks\""), std::string::npos)
            << e.what();
    }
}

}  // namespace
}  // namespace pgt
