// "filter": "gpu8" (docs/methods.md "GPU filter precision"): bilinear weights rounded to 8
// fractional bits. Oracles: where the fraction is already a multiple of 1/256 nothing changes; on a
// ramp the change is at most the slope times 1/512 texel; a constant map is unchanged; parsing.
#include <gtest/gtest.h>

#include <random>

#include "core/error.h"
#include "methods/config.h"
#include "methods/registry.h"
#include "test_util.h"

namespace pgt {
namespace {

TEST(Gpu8, WeightsOnTheLatticeAreExactAndOthersMoveByAtMostHalfAStep) {
    const double slope = 0.013;  // per texel along u
    Texture ramp = test::makeTexture(64, 8, [&](int i, int) { return 0.1 + slope * i; });
    std::mt19937 rng(3);
    std::uniform_int_distribution<int> texel(1, 60), step(0, 255);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    int moved = 0;
    for (int q = 0; q < 2000; ++q) {
        // On the lattice: x = i + k/256 in texel-centre units.
        const double x = texel(rng) + step(rng) / 256.0, y = 3.5;
        const Vec2d onLattice((x + 0.5) / 64, (y + 0.5) / 8);
        EXPECT_EQ(sampleBilinear<double>(ramp, onLattice, 0, true),
                  sampleBilinear<double>(ramp, onLattice));
        const Vec2d anywhere(0.05 + 0.9 * uni(rng), uni(rng));
        const double d = std::fabs(sampleBilinear<double>(ramp, anywhere, 0, true) -
                                   sampleBilinear<double>(ramp, anywhere));
        EXPECT_LE(d, slope / 512 + 1e-12) << q;
        moved += d > 1e-9;
    }
    EXPECT_GT(moved, 1500);
}

TEST(Gpu8, MethodsReadTheQuantisedFilterOnlyWhenAsked) {
    MethodConfig exact = test::method(R"({"name":"pom"})");
    MethodConfig gpu8 = test::method(R"({"name":"pom","filter":"gpu8"})");
    EXPECT_FALSE(exact.builtin()->gpu8Filter);
    EXPECT_TRUE(gpu8.builtin()->gpu8Filter);
    EXPECT_EQ(toJson(gpu8).value("filter", ""), "gpu8");
    EXPECT_FALSE(toJson(exact).contains("filter"));  // older studies keep their identity
    std::vector<MethodConfig> both = parseMethods(
        nlohmann::json::parse(R"(["pom", {"name":"pom","filter":"gpu8"}])"), "t", "methods");
    EXPECT_NE(both[0].label, both[1].label);
    try {
        test::method(R"({"name":"pom","filter":"gpu9"})");
        FAIL();
    } catch (const InputError& e) {
        EXPECT_NE(e.field().find("filter"), std::string::npos);
        EXPECT_EQ(e.value(), "\"gpu9\"");  // as the JSON shows it
    }
    Texture flat = test::makeTexture(16, 16, [](int, int) { return 0.4; });
    Texture ramp = test::makeTexture(64, 64, [](int i, int) { return 0.01 * i; });
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    double largest = 0;
    for (int q = 0; q < 500; ++q) {
        const Vec2f uv0(float(0.2 + 0.6 * uni(rng)), float(uni(rng)));
        const Vec3f v(viewFromAngles(70 * uni(rng), 360 * uni(rng)));
        auto run = [&](const MethodConfig& cfg, const Texture& t) {
            MethodContext<float> c;
            c.height = &t;
            c.scale = 0.05f;
            c.bias = -0.05f;
            return runMethod<float>(*cfg.builtin(), c, uv0, v);
        };
        EXPECT_EQ(run(exact, flat), run(gpu8, flat)) << q;
        largest = std::max(largest, double(glm::length(run(exact, ramp) - run(gpu8, ramp))) * 64);
    }
    EXPECT_GT(largest, 0.0);   // the filter was quantised
    EXPECT_LT(largest, 0.05);  // and moved pom by a fraction of a texel on a gentle ramp
}

}  // namespace
}  // namespace pgt
