// cone and its conservative cone map (heightfield/cone_map.h, methods/builtin/cone.h): the fast
// build equals an independent brute-force build of the same definition; pure cone stepping never
// passes the first intersection (seeded maps, scales, views; the ray checked densely and
// against test::firstHit); closed forms; more steps never hurt.
#include <gtest/gtest.h>

#include <cfloat>
#include <random>

#include "evaluate/evaluate.h"
#include "heightfield/cone_map.h"
#include "methods/registry.h"
#include "test_util.h"

namespace pgt {
namespace {

using test::makeTexture;
using test::method;

Texture roughMap(int w, int h, Address address, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    return makeTexture(
        w, h, [&](int, int) { return uni(rng); }, address);
}

// The cone map by its definition, pair by pair: O(cells^2), written apart from the build.
// `hierarchical`: each cell R through its ancestor at the level coneLevelUsed picks (the
// build's definition); otherwise R itself (the exact optimum of the cell-by-cell bound).
std::vector<float> bruteForceCone(const Texture& t, bool inverted, bool hierarchical) {
    const bool repeat = t.address == Address::Repeat;
    const int W = t.width, H = t.height;
    const int cx = repeat ? W : std::max(W - 1, 1), cy = repeat ? H : std::max(H - 1, 1);
    const double sg = inverted ? -1 : 1;
    auto e = [&](int i, int j) {
        i = repeat ? (i % W + W) % W : std::clamp(i, 0, W - 1);
        j = repeat ? (j % H + H) % H : std::clamp(j, 0, H - 1);
        return sg * t.texel(i, j);
    };
    struct Cell {
        double lo, hi, grad;
    };
    std::vector<Cell> cells;
    for (int j = 0; j < cy; ++j)
        for (int i = 0; i < cx; ++i) {
            double a = e(i, j), b = e(i + 1, j), c = e(i, j + 1), d = e(i + 1, j + 1);
            double g = 0;
            for (double gx : {b - a, d - c})
                for (double gy : {c - a, d - b}) g = std::max(g, std::hypot(gx * W, gy * H));
            cells.push_back({std::min({a, b, c, d}), std::max({a, b, c, d}), g});
        }
    int levels = 1;
    while ((1 << (levels - 1)) < std::max(cx, cy)) ++levels;
    // Lattice interval of cells [i0, i1) along an axis, and the gap between two intervals.
    auto interval = [&](int i0, int i1, int texels, int n) {
        double a = i0, b = i1;
        if (!repeat && i0 == 0) a = -0.5;
        if (!repeat && i1 == n) b = texels - 0.5;
        return std::pair{a, b};
    };
    auto gap = [&](std::pair<double, double> p, std::pair<double, double> q, int texels) {
        double best = INFINITY;
        for (int shift : repeat ? std::vector<int>{-2, -1, 0, 1, 2} : std::vector<int>{0})
            best = std::min(best, std::max({0.0, q.first + shift * texels - p.second,
                                            p.first - q.second - shift * texels}));
        return best;
    };
    const double delta = kConeBlock * std::min(1.0 / W, 1.0 / H);
    std::vector<float> out;
    for (int j = 0; j < cy; ++j)
        for (int i = 0; i < cx; ++i) {
            double g = 0;
            for (int dj = -kConeBlock; dj <= kConeBlock; ++dj)
                for (int di = -kConeBlock; di <= kConeBlock; ++di) {
                    int x = i + di, y = j + dj;
                    if (repeat)
                        x = (x % cx + cx) % cx, y = (y % cy + cy) % cy;
                    else if (x < 0 || y < 0 || x >= cx || y >= cy)
                        continue;
                    g = std::max(g, cells[size_t(y) * cx + x].grad);
                }
            double best = g > 0 ? std::min(1 / g, kConeRatioCap) : kConeRatioCap;
            const double low = cells[size_t(j) * cx + i].lo;
            for (int y = 0; y < cy; ++y)
                for (int x = 0; x < cx; ++x) {
                    int level = 0;
                    while (hierarchical && level + 1 < levels &&
                           std::max(std::abs((x >> (level + 1)) - (i >> (level + 1))),
                                    std::abs((y >> (level + 1)) - (j >> (level + 1)))) > 1)
                        ++level;
                    const int n = 1 << level, x0 = (x >> level) * n, y0 = (y >> level) * n;
                    const int x1 = std::min(x0 + n, cx), y1 = std::min(y0 + n, cy);
                    double top = -INFINITY;
                    for (int yy = y0; yy < y1; ++yy)
                        for (int xx = x0; xx < x1; ++xx)
                            top = std::max(top, cells[size_t(yy) * cx + xx].hi);
                    if (!(top > low)) continue;
                    double d =
                        std::hypot(gap(interval(i, i + 1, W, cx), interval(x0, x1, W, cx), W) / W,
                                   gap(interval(j, j + 1, H, cy), interval(y0, y1, H, cy), H) / H);
                    best = std::min(best, std::max(d, delta) / (top - low));
                }
            float f = float(best);
            if (double(f) > best) f = std::nextafter(f, 0.0f);
            out.push_back(f);
        }
    return out;
}

// The fast build equals the brute-force build of its definition on every cell, and never
// promises more than the exact cell-by-cell optimum (it is conservative against it).
TEST(Cone, FastBuildEqualsTheBruteForceOne) {
    int n = 0;
    double quality = 0;
    for (Address address : {Address::Repeat, Address::Clamp})
        for (auto [w, h] : {std::pair{16, 16}, std::pair{13, 9}, std::pair{7, 20}, std::pair{1, 5},
                            std::pair{24, 3}, std::pair{40, 33}})
            for (bool inverted : {false, true}) {
                Texture t = roughMap(w, h, address, uint32_t(w * 31 + h));
                ConeMap m = buildConeMap(t, inverted);
                std::vector<float> brute = bruteForceCone(t, inverted, true);
                std::vector<float> optimum = bruteForceCone(t, inverted, false);
                ASSERT_EQ(m.ratio.size(), brute.size());
                for (size_t k = 0; k < brute.size(); ++k, ++n) {
                    EXPECT_NEAR(m.ratio[k], brute[k], 1e-6 * brute[k])
                        << w << "x" << h << " cell " << k << " inverted " << inverted;
                    EXPECT_LE(m.ratio[k], optimum[k] * (1 + 1e-6)) << w << "x" << h << " " << k;
                    quality += m.ratio[k] / optimum[k];
                }
            }
    std::printf("cells %d; mean ratio of the build to the exact optimum %.3f\n", n, quality / n);
    EXPECT_GT(n, 1000);
}

MethodTextures withCone(const Texture& t, double s, double b) {
    MethodTextures tex = makeMethodTextures(t, s, b, UvExtent{}, false);
    tex.cone = std::make_shared<const ConeMap>(buildConeMap(t, s < 0));
    tex.relaxedCone = std::make_shared<const ConeMap>(buildRelaxedConeMap(t, *tex.cone));
    return tex;
}

template <class Real>
Vec2<Real> cone(const MethodTextures& tex, Vec2d uv0, Vec3d v, const std::string& json,
                int* fetches = nullptr, uint32_t* flags = nullptr) {
    MethodContext<Real> c = makeMethodContext<Real>(tex);
    Vec2<Real> uv = runMethod<Real>(*method(json).builtin(), c, Vec2<Real>(uv0), Vec3<Real>(v));
    if (fetches) *fetches = c.fetches;
    if (flags) *flags = c.flags;
    return uv;
}

// Pure cone stepping, in double, many steps: along the ray from the top of the relief to the
// returned point the ray never goes below the surface (checked at 4000 points and at the
// end), and the point is never beyond test::firstHit's crossing. Rough random maps (both
// address modes, sizes not powers of two), s > 0 and s < 0, views to 88 degrees.
TEST(Cone, PureConeSteppingNeverPassesTheFirstIntersection) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    int checked = 0, moved = 0;
    for (Address address : {Address::Repeat, Address::Clamp})
        for (double s : {0.05, 0.2, -0.1}) {
            Texture t = roughMap(23, 17, address, uint32_t(100 * s + 50 + int(address)));
            const double b = -0.4 * s;
            MethodTextures tex = withCone(t, s, b);
            const ConeMap& m = *tex.cone;
            for (int q = 0; q < 150; ++q) {
                Vec2d uv0(uni(rng), uni(rng));
                Vec3d v = viewFromAngles(88 * std::sqrt(uni(rng)), 360 * uni(rng));
                Vec2d got =
                    cone<double>(tex, uv0, v, R"({"name":"cone","steps":300,"refine_steps":0})");
                const Vec2d dir = Vec2d(v.x, v.y) / v.z;
                const double a = std::fabs(s), sg = s < 0 ? -1 : 1;
                const Vec2d start = uv0 + dir * (a * m.top + b);
                // The ray's e where it is at uv (along the ray from start).
                const double len = glm::length(got - start);
                auto rayE = [&](double f) {
                    return m.top - f * len / std::max(a * glm::length(dir), 1e-300);
                };
                for (int k = 0; k <= 4000; ++k) {
                    const double f = k / 4000.0;
                    const Vec2d p = start + (got - start) * f;
                    const double surface = sg * sampleBilinear<double>(t, p);
                    if (glm::length(dir) > 0) {
                        ASSERT_GE(rayE(f), surface - 1e-9) << q << " at " << f;
                    }
                }
                Vec2d hit = test::firstHit(t, s, b, uv0, v);
                EXPECT_LE(len, glm::length(hit - start) + 1e-9) << q;
                if (len > 1e-6) ++moved;
                ++checked;
            }
        }
    EXPECT_EQ(checked, 900);
    EXPECT_GT(moved, 800);
}

// On a flat map the relief's top is the surface: uv0 + V.xy/V.z * (s h + b) exactly, after one
// fetch in the cone loop and one before the refinement (and the map's ratio is at its cap). On
// a ramp the refined result is within 1e-6 texel of the exact crossing.
TEST(Cone, ClosedFormsOnConstantAndRamp) {
    const double h = double(0.37f), s = 0.08, b = -0.03;
    Texture level = makeTexture(16, 16, [&](int, int) { return h; });
    MethodTextures flat = withCone(level, s, b);
    EXPECT_EQ(flat.cone->ratio[0], float(kConeRatioCap));
    Texture ramp = makeTexture(
        64, 64, [](int i, int) { return 0.2 + 0.01 * i; }, Address::Clamp);
    MethodTextures sloped = withCone(ramp, s, b);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    for (int q = 0; q < 200; ++q) {
        Vec2d uv0(0.3 + 0.4 * uni(rng), uni(rng));
        Vec3d v = viewFromAngles(70 * uni(rng), 360 * uni(rng));
        int fetches = 0;
        Vec2d got = cone<double>(flat, uv0, v, R"({"name":"cone"})", &fetches);
        Vec2d want = uv0 + Vec2d(v.x, v.y) / v.z * (s * h + b);
        EXPECT_LT(glm::length(got - want), 1e-12) << q;
        EXPECT_EQ(fetches, 2) << q;
        Vec2d hit = test::firstHit(ramp, s, b, uv0, v);
        Vec2d r = cone<double>(sloped, uv0, v, R"({"name":"cone","steps":64,"refine_steps":20})");
        EXPECT_LT(glm::length(r - hit) * 64, 1e-6) << q;
    }
}

TEST(Cone, HeadOnReturnsUv0AndNoEyeBelow) {
    Texture t = roughMap(20, 20, Address::Repeat, 3);
    MethodTextures tex = withCone(t, 0.1, -0.05);
    for (int q = 0; q < 20; ++q) {
        Vec2d uv0(0.05 * q, 0.9 - 0.04 * q);
        EXPECT_EQ(cone<double>(tex, uv0, Vec3d(0, 0, 1), R"({"name":"cone"})"), uv0);
        EXPECT_EQ(cone<float>(tex, uv0, Vec3d(0, 0, 1), R"({"name":"cone"})"), Vec2f(uv0));
    }
    uint32_t flags = 0;
    Vec2d r =
        cone<double>(tex, Vec2d(0.5), Vec3d(0.6, 0, -0.8), R"({"name":"cone"})", nullptr, &flags);
    EXPECT_TRUE(std::isnan(r.x));
    EXPECT_TRUE(flags & kFlagZeroDivide);
}

// Pure cone steps only ever advance towards the first hit: per fragment the distance to it
// never grows with more steps (4, 16, 64), and the mean shrinks; with refinement, the mean
// error at 32 + 5 is below 4 + 5's.
TEST(Cone, MoreStepsNeverHurt) {
    Texture t = test::smoothTexture(64, 64);
    MethodTextures tex = withCone(t, 0.06, -0.03);
    std::mt19937 rng(8);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    double sum[3] = {0, 0, 0}, refined[2] = {0, 0};
    for (int q = 0; q < 500; ++q) {
        Vec2d uv0(uni(rng), uni(rng));
        Vec3d v = viewFromAngles(75 * std::sqrt(uni(rng)), 360 * uni(rng));
        Vec2d hit = test::firstHit(t, 0.06, -0.03, uv0, v);
        double prev = INFINITY;
        int k = 0;
        for (int steps : {4, 16, 64}) {
            std::string json =
                R"({"name":"cone","refine_steps":0,"steps":)" + std::to_string(steps) + "}";
            double d = glm::length(cone<double>(tex, uv0, v, json) - hit) * 64;
            EXPECT_LE(d, prev + 1e-12) << q << " steps " << steps;
            prev = d;
            sum[k++] += d;
        }
        refined[0] += glm::length(cone<double>(tex, uv0, v, R"({"name":"cone","steps":4})") - hit);
        refined[1] += glm::length(cone<double>(tex, uv0, v, R"({"name":"cone"})") - hit);
    }
    std::printf(
        "pure cone mean texels: 4 steps %.4g, 16 %.4g, 64 %.4g; refined 4+5 %.4g, "
        "32+5 %.4g\n",
        sum[0] / 500, sum[1] / 500, sum[2] / 500, refined[0] * 64 / 500, refined[1] * 64 / 500);
    EXPECT_LT(sum[1], sum[0]);
    EXPECT_LT(sum[2], sum[1]);
    EXPECT_LT(refined[1], refined[0]);
}

// The relaxed cones' promise, checked apart from their build: a ray from above texel T at the
// map's top through another texel D's surface point (D within the build's radius) enters the
// surface at most once before it reaches the side of T's cone: along it, sampled at 8,000
// points, once below the surface it is never above again. Rough maps, both address modes,
// s of both signs. The relaxed ratio is never below the conservative one of T's cells.
TEST(RelaxedCone, RaysThroughTexelsEnterAtMostOnceInsideTheCone) {
    std::mt19937 rng(12);
    int rays = 0, entered = 0;
    double wider = 0;
    for (Address address : {Address::Repeat, Address::Clamp})
        for (double s : {0.08, -0.08}) {
            Texture t = roughMap(19, 22, address, uint32_t(address == Address::Repeat ? 7 : 9));
            MethodTextures tex = withCone(t, s, -0.04);
            const ConeMap& m = *tex.relaxedCone;
            const double sg = s < 0 ? -1 : 1, W = t.width, H = t.height;
            std::uniform_int_distribution<int> ti(0, t.width - 1), tj(0, t.height - 1),
                off(-kRelaxedRadius, kRelaxedRadius);
            for (int q = 0; q < 1500; ++q) {
                const int i = ti(rng), j = tj(rng), di = off(rng), dj = off(rng);
                if (di == 0 && dj == 0) continue;
                const double c = m.ratio[size_t(j) * t.width + i];
                const double eT = sg * t.texel(i, j);
                const Vec2d T((i + 0.5) / W, (j + 0.5) / H),
                    D((i + di + 0.5) / W, (j + dj + 0.5) / H);
                const double eD = sg * sampleBilinear<double>(t, D);
                if (!(m.top > eD)) continue;
                const double rhoD = glm::length(D - T), drop = (m.top - eD) / rhoD;  // e per UV
                // Where the ray (top - drop rho) meets the cone's side (eT + rho / c).
                const double rhoEnd = (m.top - eT) / (drop + 1 / c);
                bool inside = false, violated = false;
                for (int k = 0; k <= 8000; ++k) {
                    const double rho = rhoEnd * k / 8000;
                    const Vec2d p = T + (D - T) / rhoD * rho;
                    const double gap = m.top - drop * rho - sg * sampleBilinear<double>(t, p);
                    if (gap < -1e-9) inside = true;
                    if (gap > 1e-9 && inside) violated = true;
                }
                EXPECT_FALSE(violated) << "T " << i << "," << j << " D +" << di << "," << dj;
                entered += inside;
                ++rays;
            }
            for (int j = 0; j < t.height; ++j)
                for (int i = 0; i < t.width; ++i) {
                    double safe = INFINITY;
                    for (int cj : {j - 1, j})
                        for (int ci : {i - 1, i})
                            safe = std::min(safe, double(tex.cone->ratio[size_t(coneCell(
                                                      *tex.cone, (ci + 1) / W, (cj + 1) / H))]));
                    const double c = m.ratio[size_t(j) * t.width + i];
                    EXPECT_GE(c, float(safe)) << i << "," << j;
                    wider += c / safe;
                }
        }
    std::printf("rays %d, %d entering inside their cone; relaxed / conservative ratio %.2f\n", rays,
                entered, wider / (4 * 19 * 22));
    EXPECT_GT(rays, 2000);
    EXPECT_GT(entered, 100);  // the relaxed cones do let rays in: the property is not vacuous
}

template <class Real>
Vec2<Real> relaxed(const MethodTextures& tex, Vec2d uv0, Vec3d v, const std::string& json) {
    MethodContext<Real> c = makeMethodContext<Real>(tex);
    return runMethod<Real>(*method(json).builtin(), c, Vec2<Real>(uv0), Vec3<Real>(v));
}

// Head-on: uv0. Flat map: exact. More cone steps and more binary steps never hurt on a smooth
// map (mean distance to the first hit); no eye below: NaN and the flag.
TEST(RelaxedCone, ClosedFormsAndConvergence) {
    Texture smooth = test::smoothTexture(64, 64);
    MethodTextures tex = withCone(smooth, 0.06, -0.03);
    const std::string json = R"({"name":"relaxed_cone"})";
    for (int q = 0; q < 10; ++q)
        EXPECT_EQ(relaxed<double>(tex, Vec2d(0.1 * q, 0.05), Vec3d(0, 0, 1), json),
                  Vec2d(0.1 * q, 0.05));
    const double h = double(0.6f);
    Texture level = makeTexture(8, 8, [&](int, int) { return h; });
    MethodTextures flat = withCone(level, 0.06, -0.03);
    std::mt19937 rng(14);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    double err[3] = {0, 0, 0};
    for (int q = 0; q < 400; ++q) {
        Vec2d uv0(uni(rng), uni(rng));
        Vec3d v = viewFromAngles(75 * std::sqrt(uni(rng)), 360 * uni(rng));
        Vec2d want = uv0 + Vec2d(v.x, v.y) / v.z * (0.06 * h - 0.03);
        EXPECT_LT(glm::length(relaxed<double>(flat, uv0, v, json) - want), 1e-12) << q;
        Vec2d hit = test::firstHit(smooth, 0.06, -0.03, uv0, v);
        err[0] += glm::length(
            relaxed<double>(tex, uv0, v,
                            R"({"name":"relaxed_cone","cone_steps":4,"binary_steps":2})") -
            hit);
        err[1] += glm::length(relaxed<double>(tex, uv0, v, json) - hit);
        err[2] += glm::length(
            relaxed<double>(tex, uv0, v,
                            R"({"name":"relaxed_cone","cone_steps":30,"binary_steps":12})") -
            hit);
    }
    std::printf("relaxed_cone mean texels: 4+2 %.4g, 15+6 %.4g, 30+12 %.4g\n", err[0] / 400 * 64,
                err[1] / 400 * 64, err[2] / 400 * 64);
    EXPECT_LT(err[1], err[0]);
    EXPECT_LT(err[2], err[1]);
    uint32_t flags = 0;
    MethodContext<double> c = makeMethodContext<double>(tex);
    Vec2d r = runMethod<double>(*method(json).builtin(), c, Vec2d(0.5), Vec3d(0.6, 0, -0.8));
    flags = c.flags;
    EXPECT_TRUE(std::isnan(r.x));
    EXPECT_TRUE(flags & kFlagZeroDivide);
}

}  // namespace
}  // namespace pgt
