// The GL path with mipmaps and derivatives: screen layout gives a shader the rasteriser's
// quad derivatives (dFdxFine/dFdyFine), pgt_sample with "lod": "grad" filters as the C++
// trilinear sampler does (within the GPU's filter precision), and pom with lod grad agrees
// with its GLSL twin over a frame.
#include <gtest/gtest.h>

#include <fstream>
#include <random>

#include "frame/render.h"
#include "heightfield/mipmaps.h"
#include "methods/config.h"
#include "methods/presets/presets.h"
#include "methods/shader/glsl_method.h"
#include "raster/fragment_list.h"
#include "raster/raster.h"
#include "test_util.h"
#include "truth/builder.h"

namespace pgt {
namespace {

// A GLSL method from shader text written to a temporary file.
MethodConfig inlineGlsl(const std::string& name, const std::string& source,
                        const std::string& extra = "") {
    const auto dir = test::tempDir("gl_lod_" + name);
    std::ofstream(dir / (name + ".glsl")) << source;
    return parseMethod(nlohmann::json::parse(R"({"name": ")" + name + R"(", "glsl": ")" + name +
                                             R"(.glsl", "function": "F")" + extra + "}"),
                       (dir / "scene.json").string(), "methods[0]");
}

GlslInputs screenInputs(const FragmentList& f, int w, int h) {
    GlslInputs in;
    in.uv0.assign(f.uv0.begin(), f.uv0.end());
    in.view.assign(f.view.begin(), f.view.end());
    in.uvDx.assign(f.uvDx.begin(), f.uvDx.end());
    in.uvDy.assign(f.uvDy.begin(), f.uvDy.end());
    in.pixel = f.pixel;
    in.frameWidth = w;
    in.frameHeight = h;
    return in;
}

// A shader returning dFdxFine(uv) (then dFdyFine) gets the rasteriser's derivative at every
// covered pixel of a perspective view of a plane with edges in the frame (helpers at the
// plane's border included): with "api": "d3d" y runs down the image as the rasteriser's rows
// do; with "gl" (a GLSL file's default) up, so dFdy is the rasteriser's negated; HLSL's ddy
// alike. Packed, the same shader sees unrelated neighbours.
TEST(Gl, ScreenLayoutDerivativesAreTheRasterisers) {
    BaseMesh plane = makePlaneMesh(Vec3d(0), 1.0, 1.0);
    Camera cam =
        Camera::pinhole(Vec3d(0.2, -1.1, 0.6), Vec3d(0, 0.1, 0), Vec3d(0, 0, 1), 60, 97, 63);
    const FragmentList f = compactFragments(rasterize(plane, cam, {true}));
    ASSERT_GT(f.size(), 1000u);
    const Texture t = test::smoothTexture(8, 8);
    MethodConfig dx = inlineGlsl("dx", "vec2 F(vec2 uv, vec3 V) { return dFdxFine(uv); }\n",
                                 R"(, "sampler": "")");
    MethodConfig dy = inlineGlsl("dy", "vec2 F(vec2 uv, vec3 V) { return dFdyFine(uv); }\n",
                                 R"(, "sampler": "", "api": "d3d")");
    MethodConfig dyGl = inlineGlsl("dygl", "vec2 F(vec2 uv, vec3 V) { return dFdyFine(uv); }\n",
                                   R"(, "sampler": "")");
    const auto hlslDir = test::tempDir("gl_lod_hlsl_ddy");
    std::ofstream(hlslDir / "ddy.hlsl")
        << "float2 F(float2 uv, float3 V) { return ddy_fine(uv); }\n";
    auto hlsl = [&](const char* api) {
        nlohmann::json e = {
            {"name", "ddy"}, {"hlsl", "ddy.hlsl"}, {"function", "F"}, {"sampler", ""}};
        if (*api) e["api"] = api;
        return parseMethod(e, (hlslDir / "scene.json").string(), "methods[0]");
    };
    const GlslInputs in = screenInputs(f, cam.width(), cam.height());
    GlslRun rx = runGlsl(*dx.shader(), GlslMaps{{.height = &t}}, in),
            ry = runGlsl(*dy.shader(), GlslMaps{{.height = &t}}, in),
            ryGl = runGlsl(*dyGl.shader(), GlslMaps{{.height = &t}}, in),
            hy = runGlsl(*hlsl("").shader(), GlslMaps{{.height = &t}}, in),
            hyGl = runGlsl(*hlsl("gl").shader(), GlslMaps{{.height = &t}}, in);
    double worst = 0;
    for (size_t k = 0; k < f.size(); ++k) {
        worst = std::max(worst, double(glm::length(Vec2d(rx.uv[k]) - f.uvDx[k])));
        worst = std::max(worst, double(glm::length(Vec2d(ry.uv[k]) - f.uvDy[k])));
        worst = std::max(worst, double(glm::length(Vec2d(ryGl.uv[k]) + f.uvDy[k])));
        worst = std::max(worst, double(glm::length(Vec2d(hy.uv[k]) - f.uvDy[k])));
        worst = std::max(worst, double(glm::length(Vec2d(hyGl.uv[k]) + f.uvDy[k])));
    }
    // uv0 is rounded to float (|uv| < 2: 2^-23 each) before the GL subtracts.
    EXPECT_LT(worst, 1e-6);
    // Packed, a fragment's row neighbour is the next fragment in scan order, its column
    // neighbour beyond the one-row image: dFdy is not the rasteriser's.
    GlslInputs packed = in;
    packed.frameWidth = 0;
    GlslRun py = runGlsl(*dy.shader(), GlslMaps{{.height = &t}}, packed);
    int far = 0;
    for (size_t k = 0; k < f.size(); ++k)
        far += glm::length(Vec2d(py.uv[k]) - f.uvDy[k]) > 1e-3 * glm::length(f.uvDy[k]);
    EXPECT_GT(far, int(f.size()) / 2);
}

// A map whose level 0 is 0 and every other level 1: trilinear filtering returns fract(lambda)
// for 0 < lambda < 1, so the GL's own level of detail can be read back.
Texture lodProbe(int n) {
    Texture z = test::makeTexture(n, n, [](int, int) { return 0.0; });
    auto levels = std::make_shared<std::vector<Texture>>(*buildMipChain(z));
    for (Texture& l : *levels) std::fill(l.texels.begin(), l.texels.end(), 1.0f);
    z.mips = levels;
    return z;
}

// pgt_sample with lod grad against sampleTrilinear on a mipmapped map. The GL's level of
// detail is read back first (lodProbe): the GL specification lets it approximate
// log2(rho), and llvmpipe does (measured here: up to 0.043 below the exact value, within
// 0.05 asserted). At the GL's own lambda the filter and the levels must be the C++ ones,
// within the GPU's filter precision: 8-bit weights in each bilinear fetch (slope x 1/512 texel)
// and in the mix of the two levels (|l0 - l1| / 256), plus float rounding.
TEST(Gl, TrilinearFilterMatchesTheCpp) {
    Texture t = test::smoothTexture(64, 64);
    addMipmaps(t);
    MethodConfig m =
        inlineGlsl("tri",
                   "uniform sampler2D heightMap;\n"
                   "vec2 F(vec2 uv, vec3 V) { return pgt_sample(heightMap, uv).rr; }\n",
                   R"(, "sampler": "heightMap", "lod": "grad")");
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    GlslInputs in;
    for (int k = 0; k < 4000; ++k) {
        in.uv0.push_back(Vec2f(float(uni(rng) * 3 - 1), float(uni(rng) * 3 - 1)));
        in.view.push_back(Vec3f(0, 0, 1));
        const float rho = float(std::exp2(uni(rng) * 0.98 + 0.01)) / 64.0f;  // lambda in (0, 1)
        const float a = float(uni(rng) * 6.28);
        in.uvDx.push_back(Vec2f(std::cos(a), std::sin(a)) * rho);
        in.uvDy.push_back(Vec2f(-std::sin(a), std::cos(a)) * rho * float(uni(rng)));
    }
    auto maps = [](const Texture& map) { return GlslMaps{{.height = &map}, 0, 0, nullptr, true}; };
    const Texture probe = lodProbe(64);
    GlslRun lambda = runGlsl(*m.shader(), maps(probe), in), run = runGlsl(*m.shader(), maps(t), in);
    int over = 0;
    double worst = 0, worstLod = 0;
    const double slope = 0.35 * 2 * 3.1416 * 2 / 64;  // smoothTexture's steepest, per texel
    for (size_t k = 0; k < in.uv0.size(); ++k) {
        const double exact = lodFromGradients(in.uvDx[k], in.uvDy[k], 64, 64);
        const float gl = lambda.uv[k].x;
        worstLod = std::max(worstLod, std::fabs(gl - exact));
        const double l0 = sampleBilinear<double>(t, Vec2d(in.uv0[k]));
        const double l1 = sampleBilinear<double>((*t.mips)[0], Vec2d(in.uv0[k]));
        const double tol = 2e-6 + slope / 512 + std::fabs(l0 - l1) / 256;
        const double diff = std::fabs(run.uv[k].x - sampleTrilinear<float>(t, in.uv0[k], gl));
        worst = std::max(worst, diff);
        over += diff > tol;
    }
    EXPECT_EQ(over, 0) << "largest difference " << worst;
    EXPECT_LT(worstLod, 0.05);
    EXPECT_GT(worstLod, 0.0);  // (llvmpipe approximates; a GPU that does not fails here)
}

// pom over a frame in screen layout on a mipmapped map: the lod zero twin (layered.glsl
// through pgt_sample) agrees with the C++ pom within 1e-3 texel on every pixel, as without
// mipmaps; the lod grad twin differs from C++ pom with lod grad only by the GL's
// approximation of the level of detail (above): on average a tenth of what the level of detail
// itself moves pom. Both the GL's and pgt's choice of level are measured by the study.
TEST(Gl, PomGradTwinOverAFrame) {
    const std::string shader = pgt::shaderDir() + "/layered.glsl";
    auto twin = [&](const std::string& name, const std::string& lod) {
        return R"({"name": ")" + name + R"(", "glsl": ")" + shader +
               R"(", "function": "ParallaxOcclusion", "sampler": "heightMap", "lod": ")" + lod +
               R"(", "uniforms": {"height_scale": "scale", "height_bias": "bias",
               "min_layers": 8.0, "max_layers": 32.0, "max_steps": 0}})";
    };
    const auto methods = parseMethods(
        nlohmann::json::parse(R"([{"name": "pom", "lod": "grad"}, "pom", )" +
                              twin("pom_grad_gl", "grad") + ", " + twin("pom_gl", "zero") + "]"),
        "t", "m");
    Texture map = test::bricks(256);
    addMipmaps(map);
    Scene s = test::planeScene(std::move(map), 0.05, -0.025, 60, 30, 128, methods);
    s.mipmaps = true;
    TruthBuilder builder(s);
    TruthPair truths = builder.build(s.displacement, s.truth.uncertainty);
    MethodTextureCache textures(s.height, s.uvExtent);
    RenderResult r = renderView(s, s.view(), truths, s.methods, textures,
                                TimingSpec{.repeats = 0, .maxFragments = 0, .seed = 1}, {});
    ASSERT_EQ(r.methods.size(), 4u);
    const auto& grad = r.methods[0].pixels.data;
    const auto& zero = r.methods[1].pixels.data;
    const auto& gradGl = r.methods[2].pixels.data;
    const auto& zeroGl = r.methods[3].pixels.data;
    int covered = 0;
    double worstZero = 0, gradApart = 0, lodEffect = 0;
    for (size_t p = 0; p < grad.size(); ++p) {
        if (!grad[p].covered) continue;
        ++covered;
        worstZero = std::max(worstZero, glm::length(zero[p].uv - zeroGl[p].uv) * 256);
        gradApart += glm::length(grad[p].uv - gradGl[p].uv) * 256;
        lodEffect += glm::length(grad[p].uv - zero[p].uv) * 256;
    }
    EXPECT_GT(covered, 4000);
    EXPECT_LT(worstZero, 1e-3);
    EXPECT_GT(lodEffect / covered, 0.05);  // the level of detail matters on this view
    EXPECT_LT(gradApart, 0.1 * lodEffect);
}

}  // namespace
}  // namespace pgt
