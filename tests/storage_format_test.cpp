// The height map as an engine stores it ("format": docs/methods.md "Texture storage"): unorm8
// and unorm16 round each texel to k / (2^n - 1), the truth keeps the authored map. Closed forms
// on constant maps, the GLSL path against the C++ on the same rounded map, mip levels from the
// rounded level 0, and the study's list of formats.
#include <gtest/gtest.h>

#include <cmath>

#include "frame/render.h"
#include "gl_agree.h"
#include "heightfield/mipmaps.h"
#include "test_util.h"

namespace pgt {
namespace {

// Parallax on a constant map h: uv' - uv0 is proportional to s h + b (docs/model.md §6b), so
// each format's offset is the float offset times (s q + b) / (s h + b), q the stored height.
TEST(StorageFormat, ConstantMapGivesTheStoredHeightsOffset) {
    const double h = 0.3, s = 0.06, b = -0.01;
    const Texture flat = test::makeTexture(8, 8, [&](int, int) { return h; });
    std::vector<MethodConfig> methods;
    for (const char* format : {"float", "unorm16", "unorm8"})
        methods.push_back(
            test::method(std::string(R"({"name": "parallax", "format": ")") + format + R"("})"));
    Scene sc = test::planeScene(flat, s, b, 50, 30, 32, methods);
    sc.truth.uncertainty = false;
    const RenderResult r = renderFrame(sc, {.timingRepeats = 0});
    // float(0.3) * 255 = 76.5000003: rounded to 77; * 65535 = 19660.5008: 19661.
    const double stored[3] = {double(float(h)), 19661.0 / 65535.0, 77.0 / 255.0};
    int compared = 0;
    for (size_t k = 0; k < r.fragments.data.size(); ++k) {
        const Fragment& f = r.fragments.data[k];
        if (!f.covered) continue;
        const Vec2d off = r.methods[0].pixels.data[k].uv - f.uv0;
        for (int i = 1; i < 3; ++i) {
            const Vec2d want = off * ((s * stored[i] + b) / (s * stored[0] + b));
            const Vec2d got = r.methods[i].pixels.data[k].uv - f.uv0;
            EXPECT_NEAR(got.x, want.x, 2e-6) << "format " << i << " pixel " << k;
            EXPECT_NEAR(got.y, want.y, 2e-6) << "format " << i << " pixel " << k;
        }
        ++compared;
    }
    EXPECT_GT(compared, 300);
    // unorm8 moves the offset by s (q - h) |V.xy / V.z| (1.4e-4 UV at this view), which the
    // error statistics see against the truth on the authored map.
    EXPECT_GT(r.methods[2].stats.error.mean, r.methods[0].stats.error.mean);
}

// The rounded map itself: every texel a multiple of 1/255 (1/65535), clamped to [0, 1], within
// half a step of the authored value; its mip levels are the box levels of the rounded level 0,
// rounded again.
TEST(StorageFormat, StoredMapRoundsEveryLevel) {
    Texture t =
        test::makeTexture(16, 16, [](int i, int j) { return -0.2 + 1.4 * (i * 16 + j) / 255.0; });
    addMipmaps(t);
    for (int bits : {8, 16}) {
        const double steps = double((1u << bits) - 1);
        const Texture q = storedMap(t, bits);
        for (size_t k = 0; k < q.texels.size(); ++k) {
            const double want = std::clamp(double(t.texels[k]), 0.0, 1.0);
            EXPECT_LE(std::abs(double(q.texels[k]) - want), 0.5 / steps + 1e-7) << k;
            // a multiple of the step, to float's precision (unorm16: 65535 x 6e-8)
            EXPECT_NEAR(double(q.texels[k]) * steps, std::round(double(q.texels[k]) * steps), 0.01);
        }
        ASSERT_TRUE(q.mips);
        const Texture& level1 = (*q.mips)[0];
        for (int j = 0; j < level1.height; ++j)
            for (int i = 0; i < level1.width; ++i) {
                const double box =
                    0.25 * (double(q.texel(2 * i, 2 * j)) + q.texel(2 * i + 1, 2 * j) +
                            q.texel(2 * i, 2 * j + 1) + q.texel(2 * i + 1, 2 * j + 1));
                // the box of the rounded level rounded again (a box on a half step may go
                // either way in float): within half a step, and a multiple of the step
                EXPECT_LE(std::abs(double(level1.texel(i, j)) - box), 0.5 / steps + 1e-6);
                EXPECT_NEAR(double(level1.texel(i, j)) * steps,
                            std::round(double(level1.texel(i, j)) * steps), 0.01);
            }
    }
}

// A GLSL method with "format" reads the same rounded map as the C++ one: pom's twin at unorm8
// equals the built-in pom at unorm8 within 1e-3 texel on 20,000 fragments, and both differ
// from float pom.
TEST(StorageFormat, GlslAndCppReadTheSameStoredMap) {
    const Texture bricks = test::bricks(128);
    const Texture stored = storedMap(bricks, 8);
    const MethodConfig cpu = test::method(R"({"name": "pom"})");
    const MethodConfig gl = glslTwin(cpu);
    const test::Fragments in = test::randomFragments(20000, 11);
    const test::Agreement same = test::agree(cpu, gl, stored, 0.05, -0.025, in, 1e-3);
    EXPECT_LE(same.over, same.n / 100);
    // Through the pipeline: the twin given "format": "unorm8" is held to the built-in's.
    std::vector<MethodConfig> methods = {
        test::filteredAsTheGl(test::method(R"({"name": "pom", "format": "unorm8"})")),
        test::method(R"({"name": "pom"})")};
    MethodConfig twin = glslTwin(methods[1]);
    twin.format = StorageFormat::Unorm8;
    twin.label = "twin_u8";
    methods.push_back(twin);
    Scene sc = test::planeScene(bricks, 0.05, -0.025, 60, 30, 64, methods);
    sc.truth.uncertainty = false;
    const RenderResult r = renderFrame(sc, {.timingRepeats = 0});
    int differ = 0, fromFloat = 0;
    for (size_t k = 0; k < r.fragments.data.size(); ++k) {
        if (!r.fragments.data[k].covered) continue;
        const Vec2d a = r.methods[0].pixels.data[k].uv, f = r.methods[1].pixels.data[k].uv,
                    g = r.methods[2].pixels.data[k].uv;
        differ += uvErrorTexels(a, g, 128, 128, Address::Repeat) > 1e-3;
        fromFloat += uvErrorTexels(a, f, 128, 128, Address::Repeat) > 1e-3;
    }
    EXPECT_LE(differ, 40);  // a march may flip a layer where floats tie
    EXPECT_GT(fromFloat, 100);
}

// "format" in a label, in JSON and as a study's list: "pom.format": ["float", "unorm8"].
TEST(StorageFormat, FormatIsPartOfTheConfiguration) {
    const MethodConfig m = test::method(R"({"name": "pom", "format": "unorm8"})");
    EXPECT_EQ(toJson(m)["format"], "unorm8");
    EXPECT_FALSE(toJson(test::method(R"({"name": "pom"})")).contains("format"));
    EXPECT_THROW(test::method(R"({"name": "pom", "format": "bc4"})"), InputError);
}

}  // namespace
}  // namespace pgt
