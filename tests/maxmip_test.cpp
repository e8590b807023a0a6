// maxmip and its minimum-maximum pyramid: the pyramid's bounds hold everywhere; the traced
// uv' is the exact first crossing (closed forms, the independent float64 reference vectors,
// a dense-then-bisection oracle on maps that are not powers of two, both address modes).
#include <gtest/gtest.h>

#include <fstream>
#include <random>

#include "frame/render.h"
#include "heightfield/minmax_pyramid.h"
#include "methods/config.h"
#include "methods/registry.h"
#include "test_util.h"

namespace pgt {
namespace {

using test::makeTexture;
using test::method;

MethodTextures withPyramid(const Texture& t, double s, double b) {
    MethodTextures tex = makeMethodTextures(t, s, b, 1.0, false);
    tex.pyramid = std::make_shared<const MinMaxPyramid>(buildMinMaxPyramid(t));
    return tex;
}

template <class Real>
Vec2<Real> trace(const MethodTextures& tex, Vec2d uv0, Vec3d v, int* fetches = nullptr,
                 uint32_t* flags = nullptr, const char* json = R"({"name":"maxmip"})") {
    MethodContext<Real> c = makeMethodContext<Real>(tex);
    Vec2<Real> uv = runMethod<Real>(*method(json).builtin(), c, Vec2<Real>(uv0), Vec3<Real>(v));
    if (fetches) *fetches = c.fetches;
    if (flags) *flags = c.flags;
    return uv;
}

// A random non-power-of-two map with sharp features.
Texture roughTexture(int w, int h, Address address, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    return makeTexture(
        w, h, [&](int, int) { return uni(rng); }, address);
}

// Every query's bounds contain every texel the queried cells touch (brute force through
// the address mode), for nodes at every level and any lattice position.
TEST(MaxMip, PyramidBoundsHoldEverywhere) {
    for (Address address : {Address::Repeat, Address::Clamp}) {
        for (auto [w, h] : {std::pair{32, 32}, std::pair{37, 20}, std::pair{5, 64}}) {
            Texture t = roughTexture(w, h, address, uint32_t(w * 100 + h));
            MinMaxPyramid p = buildMinMaxPyramid(t);
            std::mt19937 rng(3);
            std::uniform_int_distribution<int> pos(-150, 150), lev(0, p.top() + 1);
            for (int q = 0; q < 400; ++q) {
                const int64_t n = int64_t(1) << lev(rng);
                const int64_t x0 = pos(rng) * n / 4, y0 = pos(rng) * n / 4;
                float lo, hi;
                int reads = 0;
                latticeBounds(p, x0, y0, n, lo, hi, reads);
                EXPECT_GE(reads, 1);
                float tlo = INFINITY, thi = -INFINITY;
                for (int64_t y = y0; y <= y0 + n; ++y)
                    for (int64_t x = x0; x <= x0 + n; ++x) {
                        int i0, i1, j0, j1;
                        double f;
                        detail::texelPair(double(x), w, address, i0, i1, f);
                        detail::texelPair(double(y), h, address, j0, j1, f);
                        tlo = std::min(tlo, t.texel(i0, j0));
                        thi = std::max(thi, t.texel(i0, j0));
                    }
                EXPECT_LE(lo, tlo) << w << "x" << h << " node " << x0 << "," << y0 << " n " << n;
                EXPECT_GE(hi, thi) << w << "x" << h << " node " << x0 << "," << y0 << " n " << n;
            }
        }
    }
}

// A single cell's query is exactly its four corners (except the last column and row of a
// repeating map, whose wrapped corner is read through a two-texel node: conservative).
TEST(MaxMip, CellBoundsAreItsCorners) {
    Texture t = roughTexture(9, 7, Address::Repeat, 5);
    MinMaxPyramid p = buildMinMaxPyramid(t);
    for (int y = 0; y < 7; ++y)
        for (int x = 0; x < 9; ++x) {
            float lo, hi;
            int reads = 0;
            latticeBounds(p, x, y, 1, lo, hi, reads);
            if (x == 8 || y == 6) continue;
            const float c[4] = {t.texel(x, y), t.texel((x + 1) % 9, y), t.texel(x, (y + 1) % 7),
                                t.texel((x + 1) % 9, (y + 1) % 7)};
            EXPECT_EQ(lo, *std::min_element(c, c + 4));
            EXPECT_EQ(hi, *std::max_element(c, c + 4));
        }
}

// Constant height c: uv' = uv0 + V.xy / V.z * (s c + b); a ramp h = 0.2 + 0.6 u (clamp,
// rays inside the texel centres) has z = (s (0.2 + 0.6 u0) + b) / (1 - 0.6 s V.x / V.z).
TEST(MaxMip, ExactOnConstantAndRamp) {
    const int w = 64;
    const double c = double(0.3f);  // the texel as stored (float)
    Texture flat = makeTexture(16, 16, [&](int, int) { return c; });
    Texture ramp = makeTexture(
        w, 8, [&](int i, int) { return 0.2 + 0.6 * (i + 0.5) / w; }, Address::Clamp);
    const double s = 0.06, b = -0.03;
    MethodTextures tf = withPyramid(flat, s, b), tr = withPyramid(ramp, s, b);
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    for (int k = 0; k < 300; ++k) {
        Vec2d uv0(0.3 + 0.4 * uni(rng), 0.3 + 0.4 * uni(rng));
        Vec3d v = viewFromAngles(75 * uni(rng), 360 * uni(rng));
        const Vec2d dir(v.x / v.z, v.y / v.z);
        Vec2d want = uv0 + dir * (s * c + b);
        Vec2d got = trace<double>(tf, uv0, v);
        EXPECT_NEAR(got.x, want.x, 1e-12);
        EXPECT_NEAR(got.y, want.y, 1e-12);
        const double z = (s * (0.2 + 0.6 * uv0.x) + b) / (1.0 - s * 0.6 * dir.x);
        want = uv0 + dir * z;
        got = trace<double>(tr, uv0, v);
        // The ramp's texels are rounded to float: 6e-8 of a height, times s |V.xy / V.z|.
        EXPECT_NEAR(got.x, want.x, 3e-8) << k;
        EXPECT_NEAR(got.y, want.y, 3e-8) << k;
        Vec2f f = trace<float>(tr, uv0, v);
        EXPECT_NEAR(f.x, want.x, 2e-6) << k;
        EXPECT_NEAR(f.y, want.y, 2e-6) << k;
    }
}

// Head-on: uv0 exactly (the ray does not move in UV).
TEST(MaxMip, HeadOnReturnsUv0) {
    Texture t = roughTexture(40, 24, Address::Repeat, 9);
    MethodTextures tex = withPyramid(t, 0.1, -0.05);
    std::mt19937 rng(2);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    for (int k = 0; k < 200; ++k) {
        Vec2d uv0(uni(rng), uni(rng));
        Vec2f got = trace<float>(tex, uv0, {0, 0, 1});
        EXPECT_EQ(got.x, float(uv0.x));
        EXPECT_EQ(got.y, float(uv0.y));
    }
}

// Rough maps that are not powers of two, both address modes, s of both signs, views to 86
// degrees: maxmip (double) lands on the oracle's crossing. A dense step can jump over a
// sliver of surface the exact tracer finds; such points (the oracle deeper) are counted.
TEST(MaxMip, AgreesWithADenseOracle) {
    int compared = 0, slivers = 0;
    for (Address address : {Address::Repeat, Address::Clamp}) {
        Texture t = roughTexture(37, 21, address, 17);
        for (auto [s, b] : {std::pair{0.05, -0.025}, std::pair{0.1, 0.0}, std::pair{-0.04, 0.01}}) {
            MethodTextures tex = withPyramid(t, s, b);
            std::mt19937 rng(6);
            std::uniform_real_distribution<double> uni(0.0, 1.0);
            for (int k = 0; k < 150; ++k) {
                Vec2d uv0(uni(rng), uni(rng));
                Vec3d v = viewFromAngles(86 * std::sqrt(uni(rng)), 360 * uni(rng));
                Vec2d want = test::firstHit(t, s, b, uv0, v);
                uint32_t flags = 0;
                Vec2d got = trace<double>(tex, uv0, v, nullptr, &flags);
                EXPECT_EQ(flags, 0u);
                ++compared;
                const double e =
                    std::hypot((got.x - want.x) * t.width, (got.y - want.y) * t.height);
                if (e > 1e-6) {
                    // The exact tracer met the surface before the oracle's step did.
                    const double zGot = glm::length(got - uv0), zWant = glm::length(want - uv0);
                    EXPECT_LT(zGot, zWant) << "s " << s << " case " << k << " error " << e;
                    ++slivers;
                }
            }
        }
    }
    EXPECT_LE(slivers, compared / 100);
    RecordProperty("slivers", slivers);
}

// max_iterations bounds the walk and is flagged; V.z <= 0 is flagged, never a hang.
TEST(MaxMip, BoundsAndStiffCases) {
    Texture t = roughTexture(64, 64, Address::Repeat, 1);
    MethodTextures tex = withPyramid(t, 0.2, -0.1);
    uint32_t flags = 0;
    int fetches = 0;
    trace<float>(tex, {0.3, 0.6}, viewFromAngles(88, 30), &fetches, &flags,
                 R"({"name":"maxmip","max_iterations":3})");
    EXPECT_TRUE(flags & kFlagStepLimit);
    for (Vec3d v : {Vec3d(1, 0, 0), Vec3d(0.6, 0, -0.8)}) {
        flags = 0;
        trace<float>(tex, {0.3, 0.6}, v, &fetches, &flags);
        EXPECT_TRUE(flags & kFlagZeroDivide);
    }
}

// The outside reference: the exact first crossing of the independent float64
// implementation (tests/data/README.md). maxmip in double agrees to 5e-8 UV (the map is held in
// float32 here, in float64 there: 2^-24 of a height times s |V.xy / V.z| moves the crossing
// by up to ~1e-8 UV at 65 degrees), in float to 4e-6.
TEST(MaxMip, MatchesTheReferenceVectorsExactCrossing) {
    const std::string path = test::testDataDir() + "/reference_vectors.json";
    std::ifstream in(path);
    ASSERT_TRUE(in) << path << " not found";
    const nlohmann::json vec = nlohmann::json::parse(in);
    const auto& hm = vec["heightmap"];
    int compared = 0;
    for (const auto& c : vec["cases"]) {
        Address address = c["address"] == "clamp" ? Address::Clamp : Address::Repeat;
        Texture t = makeTexture(
            hm["W"], hm["H"],
            [&](int i, int j) { return hm["rows_from_bottom"][j][i].get<double>(); }, address);
        MethodTextures tex = withPyramid(t, c["scale"], c["bias"]);
        Vec3d v(c["V"][0].get<double>(), c["V"][1].get<double>(), c["V"][2].get<double>());
        for (size_t k = 0; k < c["uv0"].size(); ++k) {
            if (c["truth"][k].is_null()) continue;  // off the reference's finite plane
            Vec2d uv0(c["uv0"][k][0].get<double>(), c["uv0"][k][1].get<double>());
            Vec2d want(c["truth"][k][0].get<double>(), c["truth"][k][1].get<double>());
            Vec2d got = trace<double>(tex, uv0, v);
            Vec2f gotF = trace<float>(tex, uv0, v);
            EXPECT_NEAR(got.x, want.x, 5e-8) << "theta " << c["theta"] << " point " << k;
            EXPECT_NEAR(got.y, want.y, 5e-8) << "theta " << c["theta"] << " point " << k;
            EXPECT_NEAR(gotF.x, want.x, 4e-6) << "theta " << c["theta"] << " point " << k;
            EXPECT_NEAR(gotF.y, want.y, 4e-6) << "theta " << c["theta"] << " point " << k;
            ++compared;
        }
    }
    EXPECT_GT(compared, 100);
}

// The maps a study's configurations share: maxmip's pyramid is built once and survives a
// later configuration that needs Lengyel FGED 2's derived maps for the same (s, b) (the entry
// grows, it is not replaced under the methods that hold it), and a clear() between surfaces.
TEST(MaxMip, TextureCacheKeepsThePyramid) {
    Texture t = roughTexture(32, 32, Address::Repeat, 4);
    MethodTextureCache cache(t, UvExtent{});
    const MethodConfig mm = method(R"({"name":"maxmip"})"), it = method(R"({"name":"iterative"})");
    const MethodTextures& a = cache.get(mm, {0.05, -0.025});
    const MinMaxPyramid* p = a.pyramid.get();
    ASSERT_NE(p, nullptr);
    const MethodTextures& b = cache.get(it, {0.05, -0.025});
    EXPECT_EQ(&a, &b);
    EXPECT_EQ(a.pyramid.get(), p);
    EXPECT_NE(a.derived, nullptr);
    EXPECT_EQ(cache.precomputeMs(it, {0.05, -0.025}), 0.0);
    EXPECT_GE(cache.precomputeMs(mm, {0.05, -0.025}), 0.0);
    cache.clear();
    EXPECT_EQ(cache.get(mm, {0.1, 0.0}).pyramid.get(), p);  // built once per map
}

}  // namespace
}  // namespace pgt
