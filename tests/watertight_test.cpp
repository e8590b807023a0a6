// A truth with no holes (docs/model.md §5): views whose rays run exactly along the lines of
// the truth's lattice -- centred, power-of-two, axis-aligned, a surface at a round height --
// at every rate, in both passes, against what must hold there: an infinite plane's every ray
// hits, nothing counts as a hole, and the hit is the first crossing of the ray with the
// bilinear surface (a double-precision march that shares no code with the truth).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "frame/render.h"
#include "test_util.h"

namespace pgt {
namespace {

// An infinite plane framed tile-wide and centred under an orthographic view: pixel centres
// at (x + 0.5) / W of the tile, on the lattice's lines whenever rate x map size >= 2 W.
Scene alignedView(const Texture& map, double s, double b, double theta, double phi, int res,
                  int rate) {
    Scene sc =
        test::planeScene(map, s, b, theta, phi, res,
                         parseMethods(nlohmann::json::parse(R"(["none"])"), "test", "m"), rate);
    sc.plane()->infinite = true;
    sc.camera.frame = Framing::Fill;
    sc.camera.fillSize = sc.plane()->size;
    sc.truth.uncertainty = true;
    return sc;
}

struct Case {
    const char* what;
    Texture map;
    double s, b;
};

// Head-on and oblique, along both axes and their opposites, and one ulp off 90 degrees (an
// angle computed by a user's script: its direction has a 1e-16 cross component, which put a
// third of the pixels of such a view into holes before the truth was traced robustly).
const double kPhis[] = {0, 90, 180, 270, std::nextafter(90.0, 0.0)};

TEST(Watertight, GridAlignedViewsHaveNoHolesAtAnyRate) {
    const Case cases[] = {
        // A flat sheet at z = 0: s h + b = 0 everywhere.
        {"flat sheet at z = 0", test::makeTexture(32, 32, [](int, int) { return 0.5; }), 0.1,
         -0.05},
        // Bricks whose tops lie on the polygon (b = -s): their plateaus at z = 0.
        {"bricks at b = -s", test::bricks(32), 0.05, -0.05},
    };
    for (const Case& c : cases)
        for (int rate : {2, 4, 8, 16})
            for (double theta : {0.0, 60.0})
                for (double phi : kPhis) {
                    const int res = rate == 2 ? 32 : 64;  // pixel centres on the lattice's lines
                    const Scene sc = alignedView(c.map, c.s, c.b, theta, phi, res, rate);
                    const RenderResult r = renderFrame(sc, {.timingRepeats = 0});
                    const std::string where =
                        std::string(c.what) + ", rate " + std::to_string(rate) + ", theta " +
                        std::to_string(theta) + ", phi " + std::to_string(phi);
                    EXPECT_EQ(r.truthHits, int64_t(res) * res) << where;
                    EXPECT_EQ(r.truthHoles, 0) << where;
                    ASSERT_TRUE(r.haveUncertainty);
                    EXPECT_EQ(r.uncertainty.holesFine, 0) << where;
                    EXPECT_EQ(r.uncertainty.hitMismatch, 0) << where;
                }
}

// The hit is the first crossing: it lies no deeper along the ray than that of a double
// march of the bilinear surface (test::firstHit) -- a ray through a hole in a brick's wall
// meets a deeper surface behind it, several texels further along. (Shallower by up to a
// texel or two is the tessellation's: at rate 2 its flat triangles stand above the bilinear
// saddle at a brick's corner, where a grazing ray meets them first.)
TEST(Watertight, HitsAreTheFirstCrossingOfTheRay) {
    const Texture map = test::bricks(32);
    const double s = 0.05, b = -0.05;
    for (int rate : {2, 8})
        for (double phi : kPhis) {
            const Scene sc = alignedView(map, s, b, 60, phi, 64, rate);
            const RenderResult r = renderFrame(sc, {.timingRepeats = 0});
            const Vec3d v = viewFromAngles(60, phi);
            int compared = 0, deeper = 0;
            for (size_t k = 0; k < r.truth.size(); ++k) {
                const TruthSample& t = r.truth.data[k];
                const Fragment& f = r.fragments.data[k];
                if (!t.hit || !f.covered) continue;
                // 2,000 steps: 2.5e-5 UV in height, far finer than a texel along the ray.
                const Vec2d uv = test::firstHit(map, s, b, f.uv0, v, 2000);
                const double depth = -(s * sampleBilinear<double>(map, uv) + b) / v.z;
                ++compared;
                // A texel deeper along the ray: what a hole does, never the tessellation.
                deeper += (t.depth - depth) * 32 > 1.0;
            }
            EXPECT_EQ(compared, 64 * 64) << "rate " << rate << " phi " << phi;
            EXPECT_EQ(deeper, 0) << "rate " << rate << " phi " << phi;
        }
}

// An infinite plane seen at 89.999 degrees: the view spans thousands of tiles, which the
// truth walks periodically; it is traced, not refused by a memory estimate of a window it
// never builds.
TEST(Watertight, AnInfinitePlaneAtNearlyGrazingIsTraced) {
    Scene sc = alignedView(test::smoothTexture(32, 32), 0.05, -0.025, 89.999, 30, 64, 2);
    sc.truth.uncertainty = false;
    const RenderResult r = renderFrame(sc, {.timingRepeats = 0});
    EXPECT_EQ(r.truthHoles, 0);
    EXPECT_GT(r.truthHits, 0);
}

}  // namespace
}  // namespace pgt
