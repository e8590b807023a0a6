// Rasteriser: top-left rule on shared edges, perspective-correct UV, tangent-space V.
#include "raster/raster.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "frame/render.h"
#include "raster/fragment_list.h"
#include "raster_reference.h"
#include "scene/scene.h"
#include "test_util.h"

namespace pgt {
namespace {

BaseMesh singleTriangle(const BaseMesh& m, int tri) {
    BaseMesh out = m;
    out.indices = {m.indices[3 * tri], m.indices[3 * tri + 1], m.indices[3 * tri + 2]};
    return out;
}

// Pixels on the shared diagonal belong to exactly one of the two triangles (top-left rule):
// no pixel twice, none lost.
TEST(Raster, SharedEdgeIsCoveredExactlyOnce) {
    BaseMesh plane = makePlaneMesh(Vec3d(0), 1.0, 1.0);
    std::mt19937 rng(31);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    for (int k = 0; k < 20; ++k) {
        // Small resolutions make pixel centres land on the diagonal often.
        int res = 8 + k;
        Camera cam =
            k % 2 ? Camera::orthographic(-viewFromAngles(uni(rng) * 60, uni(rng) * 360), Vec3d(0),
                                         Vec3d(0, 0, 1) + Vec3d(0.1, 0.2, 0), 1.5, res, res)
                  : Camera::orthographic(Vec3d(0, 0, -1), Vec3d(0), Vec3d(0, 1, 0), 1.0, res, res);
        auto a = rasterize(singleTriangle(plane, 0), cam, {true});
        auto b = rasterize(singleTriangle(plane, 1), cam, {true});
        auto both = rasterize(plane, cam, {true});
        for (size_t p = 0; p < a.size(); ++p) {
            EXPECT_FALSE(a.data[p].covered && b.data[p].covered) << "pixel " << p << " case " << k;
            EXPECT_EQ(a.data[p].covered || b.data[p].covered, both.data[p].covered);
        }
    }
}

// Head-on, the plane fills pixel centres exactly: an 8x8 image of the unit plane covers all
// 64 pixels and uv0 is the pixel centre's UV.
TEST(Raster, HeadOnPixelCentresMapToUv) {
    BaseMesh plane = makePlaneMesh(Vec3d(0), 1.0, 1.0);
    Camera cam = Camera::orthographic(Vec3d(0, 0, -1), Vec3d(0), Vec3d(0, 1, 0), 1.0, 8, 8);
    RasterStats st;
    auto f = rasterize(plane, cam, {true}, &st);
    EXPECT_EQ(st.covered, 64);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            EXPECT_NEAR(f.at(x, y).uv0.x, (x + 0.5) / 8, 1e-12);
            EXPECT_NEAR(f.at(x, y).uv0.y, 1 - (y + 0.5) / 8, 1e-12);  // image y down, v up
        }
}

// Perspective-correct interpolation: uv0 equals the UV where the pixel's ray meets z = 0.
TEST(Raster, PerspectiveCorrectUvMatchesRayPlaneIntersection) {
    BaseMesh plane = makePlaneMesh(Vec3d(0), 2.0, 3.0);  // l = 2/3 world units per UV
    Camera cam =
        Camera::pinhole(Vec3d(0.3, -2.5, 1.2), Vec3d(0, 0.2, 0), Vec3d(0, 0, 1), 50, 96, 64);
    auto f = rasterize(plane, cam, {true});
    int covered = 0;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 96; ++x) {
            if (!f.at(x, y).covered) continue;
            ++covered;
            Ray r = cam.pixelRay(x, y);
            double t = -r.origin.z / r.dir.z;
            Vec3d p = r.origin + r.dir * t;
            Vec2d uv((p.x + 1) * 1.5, (p.y + 1) * 1.5);
            ASSERT_NEAR(f.at(x, y).uv0.x, uv.x, 1e-9) << x << "," << y;
            ASSERT_NEAR(f.at(x, y).uv0.y, uv.y, 1e-9) << x << "," << y;
            Vec3d v = glm::normalize(cam.eye() - p);
            ASSERT_NEAR(f.at(x, y).viewTangent.z, v.z, 1e-9);
        }
    EXPECT_GT(covered, 1000);
}

// An orthographic view from (theta, phi) gives V = docs/model.md §4's direction at every pixel.
TEST(Raster, OrthographicViewVectorIsTheViewAngle) {
    Scene s = test::planeScene(test::smoothTexture(8, 8), 0.05, -0.025, 63, 217, 64, {});
    Camera cam = makeCamera(s);
    auto f = rasterize(makePlaneMesh(Vec3d(0), 1, 1), cam, {true});
    Vec3d want = viewFromAngles(63, 217);
    int covered = 0;
    for (const auto& fr : f.data) {
        if (!fr.covered) continue;
        ++covered;
        EXPECT_NEAR(fr.viewTangent.x, want.x, 1e-12);
        EXPECT_NEAR(fr.viewTangent.y, want.y, 1e-12);
        EXPECT_NEAR(fr.viewTangent.z, want.z, 1e-12);
    }
    EXPECT_GT(covered, 500);
}

TEST(Raster, BackFacesAreCulledOnRequest) {
    BaseMesh plane = makePlaneMesh(Vec3d(0), 1.0, 1.0);
    Camera below = Camera::pinhole(Vec3d(0, 0, -2), Vec3d(0), Vec3d(0, 1, 0), 60, 32, 32);
    RasterStats culled, drawn;
    rasterize(plane, below, {true}, &culled);
    rasterize(plane, below, {false}, &drawn);
    EXPECT_EQ(culled.covered, 0);
    EXPECT_EQ(culled.trianglesCulled, 2);
    EXPECT_GT(drawn.covered, 100);
}

// A pinhole eye just above the plane: triangles crossing the near plane are clipped, not lost.
TEST(Raster, NearPlaneClippingKeepsTheVisiblePart) {
    BaseMesh plane = makePlaneMesh(Vec3d(0), 1.0, 1.0);
    Camera cam =
        Camera::pinhole(Vec3d(0, -0.45, 0.01), Vec3d(0, 0.5, 0), Vec3d(0, 0, 1), 90, 64, 64);
    RasterStats st;
    auto f = rasterize(plane, cam, {true}, &st);
    EXPECT_GT(st.covered, 200);
    for (const auto& fr : f.data)
        if (fr.covered) {
            EXPECT_TRUE(allFinite(fr.uv0) && allFinite(fr.viewTangent));
        }
}

}  // namespace
}  // namespace pgt

namespace pgt {
namespace {

// Every field the methods and the outputs read, bit for bit.
void expectSameFragments(const Image2D<Fragment>& a, const Image2D<Fragment>& b,
                         const std::string& what) {
    ASSERT_EQ(a.width, b.width);
    ASSERT_EQ(a.height, b.height);
    int64_t differ = 0;
    for (size_t k = 0; k < a.size(); ++k) {
        const Fragment &p = a.data[k], &q = b.data[k];
        bool same = p.covered == q.covered;
        if (same && p.covered)
            same = p.uv0 == q.uv0 && p.viewTangent == q.viewTangent &&
                   p.viewTangentExact == q.viewTangentExact && p.exactFrame == q.exactFrame;
        differ += !same;
    }
    EXPECT_EQ(differ, 0) << what;
}

// The binned rasteriser against the whole-frame one it replaced (tests/raster_reference.cpp),
// on every bundled scene: its own camera, and views from head-on to 89 degrees at a size
// that is no multiple of the bin (pinhole scenes keep their eye, so near-plane clipping is
// exercised by stones_pinhole and the stress eye_a_hair_above).
TEST(Raster, BinnedEqualsTheWholeFrameRasteriserOnEveryBundledScene) {
    int scenes = 0;
    for (const char* dir : {"", "stress"})
        for (const auto& entry :
             std::filesystem::directory_iterator(std::filesystem::path(test::sceneDir()) / dir)) {
            if (entry.path().extension() != ".json") continue;
            Scene scene = loadScene(entry.path().string());
            ++scenes;
            std::vector<ViewSpec> views = {scene.view()};
            for (double theta : {0.0, 45.0, 80.0, 89.0}) {
                ViewSpec v = scene.view();
                v.camera.theta = theta;
                v.camera.phi = 30;
                v.camera.width = 97;
                v.camera.height = 83;
                views.push_back(v);
            }
            for (const ViewSpec& v : views) {
                const Camera cam = makeCamera(scene, v);
                const BaseMesh mesh = drawnBaseMesh(scene.base, cam);
                RasterStats s1, s2;
                auto binned = rasterize(mesh, cam, {scene.cullBackFaces, scene.worldPerUv()}, &s1);
                auto whole =
                    reference::rasterize(mesh, cam, {scene.cullBackFaces, scene.worldPerUv()}, &s2);
                const std::string what =
                    entry.path().filename().string() + " theta " + std::to_string(v.camera.theta);
                expectSameFragments(binned, whole, what);
                EXPECT_EQ(s1.covered, s2.covered) << what;
                EXPECT_EQ(s1.noExactFrame, s2.noExactFrame) << what;
                EXPECT_EQ(s1.trianglesDrawn, s2.trianglesDrawn) << what;
                EXPECT_EQ(s1.trianglesCulled, s2.trianglesCulled) << what;
            }
        }
    EXPECT_GE(scenes, 20);
}

// Any rectangle on its own equals the same pixels of the whole frame.
TEST(Raster, AnyRectangleEqualsTheWholeFrame) {
    Scene scene = loadScene(test::sceneDir() + "/torus.json");
    ViewSpec v = scene.view();
    v.camera.width = 150, v.camera.height = 70;
    const Camera cam = makeCamera(scene, v);
    const BaseMesh mesh = drawnBaseMesh(scene.base, cam);
    auto whole = rasterize(mesh, cam, {scene.cullBackFaces, scene.worldPerUv()});
    Rasterizer raster(mesh, cam, {scene.cullBackFaces, scene.worldPerUv()});
    std::mt19937 rng(5);
    for (int k = 0; k < 40; ++k) {
        int x0 = int(rng() % 150), y0 = int(rng() % 70);
        PixelRect r{x0, y0, x0 + 1 + int(rng() % uint32_t(150 - x0)),
                    y0 + 1 + int(rng() % uint32_t(70 - y0))};
        Image2D<Fragment> part;
        RasterStats st;
        raster.rasterize(r, part, st);
        Image2D<Fragment> cut(r.width(), r.height());
        for (int y = r.y0; y < r.y1; ++y)
            for (int x = r.x0; x < r.x1; ++x) cut.at(x - r.x0, y - r.y0) = whole.at(x, y);
        expectSameFragments(part, cut, "rect " + std::to_string(k));
    }
}

FragmentList numberedFragments(int n) {
    FragmentList all;
    for (int k = 0; k < n; ++k) {
        all.pixel.push_back(k);
        all.uv0.push_back(Vec2d(k, 0));
        all.view.push_back(Vec3d(0, 0, 1));
        all.viewExact.push_back(Vec3d(0, 0, 1));
        all.uvDx.push_back(Vec2d(0));
        all.uvDy.push_back(Vec2d(0));
    }
    return all;
}

// The timing subset is a uniform sample: over 4000 seeds each of 1000 fragments is kept
// about count / n = 5 % of the time (binomial: 200 +- 14 per fragment; every one within
// 6 sigma, and the spread of the counts is the binomial one), in the order they came, and
// the same whatever lists the fragments came in.
TEST(Raster, TimingSubsetIsUniformAndIndependentOfTheSplit) {
    const int n = 1000, count = 50, seeds = 4000;
    const FragmentList all = numberedFragments(n);
    std::vector<int> kept(n, 0);
    for (int seed = 1; seed <= seeds; ++seed) {
        FragmentList sub = sampleFragments(all, count, uint32_t(seed));
        ASSERT_EQ(sub.size(), size_t(count));
        for (size_t k = 0; k < sub.size(); ++k) {
            ++kept[size_t(sub.pixel[k])];
            if (k > 0) {
                ASSERT_LT(sub.pixel[k - 1], sub.pixel[k]) << "seed " << seed;
            }
        }
    }
    const double p = double(count) / n, mean = seeds * p, sigma = std::sqrt(seeds * p * (1 - p));
    double var = 0;
    for (int k = 0; k < n; ++k) {
        EXPECT_NEAR(kept[size_t(k)], mean, 6 * sigma) << "fragment " << k;
        var += (kept[size_t(k)] - mean) * (kept[size_t(k)] - mean) / n;
    }
    EXPECT_NEAR(std::sqrt(var), sigma, 0.15 * sigma);
    // Split into lists of 1, 7 and the rest: the same subset.
    FragmentSampler split(count, 9);
    FragmentList parts[3];
    for (int k = 0; k < n; ++k) {
        FragmentList one = numberedFragments(1);
        one.pixel[0] = k;
        parts[k < 1 ? 0 : k < 8 ? 1 : 2].append(one);
    }
    for (const FragmentList& part : parts) split.add(part);
    EXPECT_EQ(split.take().pixel, sampleFragments(all, count, 9).pixel);
    // Fewer fragments than the count: all of them.
    EXPECT_EQ(sampleFragments(numberedFragments(30), count, 3).size(), 30u);
}

}  // namespace
}  // namespace pgt
