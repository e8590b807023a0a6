// Mipmaps and "lod": "grad" (heightfield/mipmaps.h, texture.h sampleTrilinear and
// lodFromGradients): the chain's sizes and box means, the GL specification's level of detail
// in closed form, trilinear filtering at its end points, the rasteriser's quad derivatives
// against the neighbours' uv0 and in closed form, and a method reading a coarser level.
#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "evaluate/evaluate.h"
#include "frame/render.h"
#include "heightfield/mipmaps.h"
#include "methods/registry.h"
#include "raster/raster.h"
#include "scene/scene.h"
#include "test_util.h"
#include "truth/builder.h"

namespace pgt {
namespace {

Texture randomTexture(int w, int h, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    return test::makeTexture(w, h, [&](int, int) { return uni(rng); });
}

double mean(const Texture& t) {
    double sum = 0;
    for (float v : t.texels) sum += v;
    return sum / double(t.texels.size());
}

// Sizes halve (floor, at least 1) down to 1 x 1; every level keeps the mean of level 0 (an
// area-weighted box loses no mass, odd sides included); on even sides a texel is the mean of
// its 2 x 2 block.
TEST(Mipmaps, ChainHalvesAndKeepsTheMean) {
    const int sizes[][2] = {{256, 64}, {5, 3}, {1, 7}, {12, 9}};
    for (const auto& size : sizes) {
        Texture t = randomTexture(size[0], size[1], 3);
        auto chain = buildMipChain(t);
        int w = t.width, h = t.height;
        for (const Texture& level : *chain) {
            w = std::max(1, w / 2), h = std::max(1, h / 2);
            EXPECT_EQ(level.width, w);
            EXPECT_EQ(level.height, h);
            EXPECT_NEAR(mean(level), mean(t), 1e-6) << size[0] << "x" << size[1];
        }
        EXPECT_EQ(chain->back().width, 1);
        EXPECT_EQ(chain->back().height, 1);
    }
    Texture t = randomTexture(8, 4, 5);
    auto chain = buildMipChain(t);
    ASSERT_EQ(chain->size(), 3u);
    const Texture& l1 = (*chain)[0];
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 4; ++i) {
            double block = (double(t.texel(2 * i, 2 * j)) + t.texel(2 * i + 1, 2 * j) +
                            t.texel(2 * i, 2 * j + 1) + t.texel(2 * i + 1, 2 * j + 1)) /
                           4;
            EXPECT_NEAR(l1.texel(i, j), block, 1e-7);
        }
}

// GL 4.6 eq. 8.6-8.7: rho = the longer of the two texel-space derivative vectors.
TEST(Mipmaps, LevelOfDetailInClosedForm) {
    const double w = 256, h = 128;
    EXPECT_DOUBLE_EQ(lodFromGradients(Vec2d(1 / w, 0), Vec2d(0, 1 / h), 256, 128), 0.0);
    EXPECT_DOUBLE_EQ(lodFromGradients(Vec2d(4 / w, 0), Vec2d(0, 1 / h), 256, 128), 2.0);
    EXPECT_DOUBLE_EQ(lodFromGradients(Vec2d(3 / w, 4 / h), Vec2d(0, 1 / h), 256, 128),
                     std::log2(5.0));
    EXPECT_DOUBLE_EQ(lodFromGradients(Vec2d(0, 0), Vec2d(0, 0.5 / h), 256, 128), -1.0);
    EXPECT_EQ(lodFromGradients(Vec2d(INFINITY, 0), Vec2d(0, 0), 256, 128), INFINITY);
    EXPECT_EQ(lodFromGradients(Vec2d(NAN, 0), Vec2d(0, 0), 256, 128), INFINITY);
}

// lod <= 0 is level 0; an integer lod is that level; half-way is the mean of the two
// levels; beyond the last level, the last level (the map's mean).
TEST(Mipmaps, TrilinearEndPoints) {
    Texture t = randomTexture(16, 16, 9);
    addMipmaps(t);
    const auto& levels = *t.mips;
    std::mt19937 rng(2);
    std::uniform_real_distribution<double> uni(-1.0, 2.0);
    for (int k = 0; k < 200; ++k) {
        Vec2d uv(uni(rng), uni(rng));
        const double l0 = sampleBilinear<double>(t, uv), l1 = sampleBilinear<double>(levels[0], uv);
        EXPECT_EQ(sampleTrilinear<double>(t, uv, -0.5), l0);
        EXPECT_EQ(sampleTrilinear<double>(t, uv, 0.0), l0);
        EXPECT_NEAR(sampleTrilinear<double>(t, uv, 1.0), l1, 1e-15);
        EXPECT_NEAR(sampleTrilinear<double>(t, uv, 0.5), (l0 + l1) / 2, 1e-15);
        EXPECT_NEAR(sampleTrilinear<double>(t, uv, 9.0), mean(t), 1e-6);
        EXPECT_NEAR(sampleTrilinear<double>(t, uv, INFINITY), mean(t), 1e-6);
    }
    Texture plain = randomTexture(16, 16, 9);  // no mipmaps: level 0 at any lod
    EXPECT_EQ(sampleTrilinear<double>(plain, Vec2d(0.3, 0.7), 3.0),
              sampleBilinear<double>(plain, Vec2d(0.3, 0.7)));
}

// Head-on, orthographic, a 1 x 1 plane in W pixels: uv changes by exactly 1/W per pixel
// (v down the image). At an angle and in perspective the fine quad differences equal the
// differences of the neighbours' uv0 (a plane's triangles share one projective map).
TEST(Raster, QuadDerivativesOfUv) {
    BaseMesh plane = makePlaneMesh(Vec3d(0), 1.0, 1.0);
    Camera head = Camera::orthographic(Vec3d(0, 0, -1), Vec3d(0), Vec3d(0, 1, 0), 1.0, 16, 16);
    auto f = rasterize(plane, head, {true});
    for (const Fragment& g : f.data) {
        ASSERT_TRUE(g.covered);
        EXPECT_NEAR(g.uvDx.x, 1.0 / 16, 1e-12);
        EXPECT_NEAR(g.uvDx.y, 0.0, 1e-12);
        EXPECT_NEAR(g.uvDy.x, 0.0, 1e-12);
        EXPECT_NEAR(g.uvDy.y, -1.0 / 16, 1e-12);
    }
    const Camera cams[] = {
        Camera::pinhole(Vec3d(0.3, -2.5, 1.2), Vec3d(0, 0.2, 0), Vec3d(0, 0, 1), 50, 96, 64),
        Camera::orthographic(-viewFromAngles(70, 30), Vec3d(0), Vec3d(0, 0, 1), 1.5, 64, 64)};
    for (const Camera& cam : cams) {
        auto img = rasterize(plane, cam, {true});
        int checked = 0;
        for (int y = 0; y < img.height; ++y)
            for (int x = 0; x < img.width; ++x) {
                const Fragment& g = img.at(x, y);
                const int nx = x ^ 1, ny = y ^ 1;
                if (!g.covered || nx >= img.width || ny >= img.height) continue;
                const Fragment &gx = img.at(nx, y), &gy = img.at(x, ny);
                const double sx = (x & 1) ? -1 : 1, sy = (y & 1) ? -1 : 1;
                if (gx.covered) {
                    EXPECT_NEAR(glm::length(g.uvDx - (gx.uv0 - g.uv0) * sx), 0, 1e-12);
                    ++checked;
                }
                if (gy.covered) {
                    EXPECT_NEAR(glm::length(g.uvDy - (gy.uv0 - g.uv0) * sy), 0, 1e-12);
                }
            }
        EXPECT_GT(checked, 250);
    }
}

// A one-texel checkerboard's level 1 is 0.5 everywhere: "parallax" with lod grad at a level
// of detail >= 1 sees h = 0.5 (closed form), with lod zero the checkerboard.
TEST(Mipmaps, GradMethodReadsTheCoarserLevel) {
    Texture t = test::makeTexture(32, 32, [](int i, int j) { return (i + j) % 2 ? 1.0 : 0.0; });
    addMipmaps(t);
    MethodTextures tex = makeMethodTextures(t, 0.05, -0.025, UvExtent{}, false);
    FragmentList frags;
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    for (int k = 0; k < 100; ++k) {
        frags.pixel.push_back(k);
        frags.uv0.push_back({uni(rng), uni(rng)});
        Vec3d v = glm::normalize(Vec3d(uni(rng) - 0.5, uni(rng) - 0.5, 0.5 + uni(rng)));
        frags.view.push_back(v);
        frags.viewExact.push_back(v);
        const double scale = 1.5 + 3 * uni(rng);  // rho 1.5-4.5 texels: lod 0.58-2.17
        frags.uvDx.push_back(Vec2d(scale / 32, 0));
        frags.uvDy.push_back(Vec2d(0, scale / 32 * uni(rng)));
    }
    MethodConfig grad = test::method(R"({"name": "parallax", "lod": "grad"})");
    MethodConfig zero = test::method(R"({"name": "parallax"})");
    auto a = evaluateMethod(grad, frags, tex, 100, 1);
    auto b = evaluateMethod(zero, frags, tex, 100, 1);
    int coarse = 0, differ = 0;
    for (int k = 0; k < 100; ++k) {
        const double lod = lodFromGradients(frags.uvDx[size_t(k)], frags.uvDy[size_t(k)], 32, 32);
        const Vec3d v = frags.view[size_t(k)];
        if (lod >= 1) {
            Vec2d expect = frags.uv0[size_t(k)] + Vec2d(v.x, v.y) / v.z * (0.05 * 0.5 - 0.025);
            EXPECT_NEAR(glm::length(a.data[size_t(k)].uv - expect), 0, 1e-6);
            ++coarse;
        }
        differ += glm::length(a.data[size_t(k)].uv - b.data[size_t(k)].uv) > 1e-4;
    }
    EXPECT_GT(coarse, 50);
    EXPECT_GT(differ, 50);
}

// uv0's derivatives are made for a frame whose configurations read them (a "lod": "grad"
// method without any GL draw here) and only then: the other methods' pixels are the same bits
// either way. A prepared view (pgt fit) makes them for the list it is given, which may be
// the fit's own and not the scene's.
TEST(Mipmaps, DerivativesAreMadeWhereAConfigurationReadsThem) {
    Texture map = test::bricks(64);
    addMipmaps(map);
    const std::vector<MethodConfig> both =
        parseMethods(nlohmann::json::parse(R"(["pom", {"name": "pom", "lod": "grad"}])"), "t", "m");
    const std::vector<MethodConfig> plain(both.begin(), both.begin() + 1);
    Scene s = test::planeScene(std::move(map), 0.05, -0.025, 60, 30, 64, plain);
    s.mipmaps = true;
    EXPECT_FALSE(rasterOptions(s, s.view(), plain).uvDerivatives);
    EXPECT_TRUE(rasterOptions(s, s.view(), both).uvDerivatives);
    TruthBuilder builder(s);
    TruthPair truths = builder.build(s.displacement, false);
    MethodTextureCache textures(s.height, s.uvExtent);
    const TimingSpec none{.repeats = 0, .maxFragments = 0, .seed = 1};
    const RenderResult a = renderView(s, s.view(), truths, plain, textures, none);
    const RenderResult b = renderView(s, s.view(), truths, both, textures, none);
    ASSERT_EQ(b.methods.size(), 2u);
    int covered = 0;
    double lodEffect = 0;
    for (size_t p = 0; p < a.fragments.data.size(); ++p) {
        const Vec2d pa = a.methods[0].pixels.data[p].uv, pb = b.methods[0].pixels.data[p].uv;
        EXPECT_EQ(std::memcmp(&pa, &pb, sizeof pa), 0) << p;
        if (!a.fragments.data[p].covered) continue;
        ++covered;
        EXPECT_EQ(a.fragments.data[p].uvDx, Vec2d(0));
        EXPECT_GT(glm::length(b.fragments.data[p].uvDx), 0);
        lodEffect += glm::length(b.methods[1].pixels.data[p].uv - pb) * 64;
    }
    EXPECT_GT(covered, 1000);
    EXPECT_GT(lodEffect / covered, 0.01);  // the grad method read levels above 0
    const PreparedView pa = prepareView(s, s.view(), truths, plain);
    const PreparedView pb = prepareView(s, s.view(), truths, both);
    size_t fragments = 0;
    for (size_t i = 0; i < pb.bands.size(); ++i) {
        const FragmentList &fa = pa.bands[i].frags, &fb = pb.bands[i].frags;
        fragments += fb.size();
        EXPECT_TRUE(fa.uvDx.empty() && fa.viewExact.empty());
        EXPECT_TRUE(fb.hasDerivatives());
        for (size_t k = 0; k < fa.size(); ++k) EXPECT_EQ(fa.viewExactAt(k), fa.view[k]);
    }
    EXPECT_EQ(fragments, size_t(covered));
}

// Lengyel FGED 2's derived maps of a mipmapped map get their own chains (each level the box mean of
// the derived map, not derived from the coarser height level), so their readers filter too.
TEST(Mipmaps, DerivedMapsHaveChains) {
    Texture t = randomTexture(16, 8, 7);
    addMipmaps(t);
    DerivedMaps d = makeDerivedMaps(t, 0.05, -0.02);
    ASSERT_TRUE(d.normal.mips && d.parallax.mips);
    EXPECT_EQ(d.normal.mips->size(), t.mips->size());
    EXPECT_NEAR(mean(d.parallax.mips->back()), mean(d.parallax), 1e-6);
    EXPECT_FALSE(makeDerivedMaps(randomTexture(16, 8, 7), 0.05, -0.02).normal.mips);
}

// "lod": "grad" needs the map's mipmaps; "mipmaps" builds them; a bad value is named.
TEST(Mipmaps, SceneFields) {
    auto scene = [](const std::string& heightmap, const std::string& method) {
        return nlohmann::json::parse(R"({"heightmap": {"procedural": "bricks", "size": [64, 64])" +
                                     heightmap + R"(}, "base": {"type": "plane"},
            "camera": {"type": "orthographic", "theta": 30, "resolution": [8, 8]},
            "methods": [)" + method + "]}");
    };
    Scene s = parseScene(scene(R"(, "mipmaps": true)", R"("pom", {"name": "pom", "lod": "grad"})"),
                         "m.json");
    ASSERT_TRUE(s.height.mips);
    EXPECT_EQ(s.height.mips->size(), 6u);
    EXPECT_TRUE(s.methods[1].lodGrad);
    EXPECT_EQ(s.methods[1].label, s.methods[0].label + "_grad");
    EXPECT_EQ(toJson(s.methods[1])["lod"], "grad");
    EXPECT_FALSE(toJson(test::method(R"("pom")")).contains("lod"));
    try {
        parseScene(scene("", R"({"name": "pom", "lod": "grad"})"), "m.json");
        FAIL();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("methods[0].lod"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("mipmaps"), std::string::npos) << e.what();
    }
    EXPECT_THROW(parseScene(scene(R"(, "mipmaps": 3)", R"("pom")"), "m.json"), InputError);
    EXPECT_THROW(
        parseScene(scene(R"(, "mipmaps": true)", R"({"name": "pom", "lod": "auto"})"), "m.json"),
        InputError);
}

}  // namespace
}  // namespace pgt
