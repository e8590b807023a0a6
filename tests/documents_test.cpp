// Each method against its source document's own code, transcribed line by line below (float,
// the documents' order of operations), at the document's native settings. These are the
// oracles the methods must reproduce; docs/model.md §3 gives the (s, b) each document implies.
#include <gtest/gtest.h>

#include "frame/render.h"
#include "methods/registry.h"
#include "test_util.h"

namespace pgt {
namespace {

using vec2 = Vec2f;
using vec3 = Vec3f;

// GLSL-like helpers for the transcriptions.
struct Doc {
    const Texture* height;
    // A depth map d = 1 - h, as LearnOpenGL and the deferred-renderer blog store it
    // ("texture(depthMap, uv).r").
    float depthTex(vec2 uv) const { return 1.0f - sampleBilinear<float>(*height, uv); }
    float heightTex(vec2 uv) const { return sampleBilinear<float>(*height, uv); }
};

// Welsh 2004 §4.2, ARB_fragment_program: TEX height; MAD height, height, 0.04, -0.02; RCP temp,
// eyevects.z; MUL height, height, temp; MAD newtexcoord, height, eyevects, texcoord.
vec2 welshParallax(const Doc& d, vec2 texcoord, vec3 eyevects) {
    float height = d.heightTex(texcoord);
    height = height * 0.04f + -0.02f;
    float temp = 1.0f / eyevects.z;
    height = height * temp;
    return vec2(height * eyevects.x + texcoord.x, height * eyevects.y + texcoord.y);
}

// Welsh 2004 §4.3: the same without RCP/MUL.
vec2 welshOffsetLimited(const Doc& d, vec2 texcoord, vec3 eyevects) {
    float height = d.heightTex(texcoord);
    height = height * 0.04f + -0.02f;
    return vec2(height * eyevects.x + texcoord.x, height * eyevects.y + texcoord.y);
}

// LearnOpenGL ParallaxMapping (depth map, height_scale): texCoords - viewDir.xy / viewDir.z *
// (height
// * height_scale).
vec2 learnOpenGLParallax(const Doc& d, vec2 texCoords, vec3 viewDir, float height_scale) {
    float height = d.depthTex(texCoords);
    vec2 p = vec2(viewDir.x, viewDir.y) / viewDir.z * (height * height_scale);
    return texCoords - p;
}

// the deferred-renderer blog ParallaxMapping: 100 fixed steps at ParallaxHeightScale 0.15
// (numLayers is computed but unused; the POM tail after `return currentTexCoords;` is unreachable).
vec2 deferredBlogSteep(const Doc& d, vec2 texCoords, vec3 viewDir, bool runTail) {
    const float ParallaxSteps = 100.0f, ParallaxHeightScale = 0.15f;
    float numSteps = std::min(100.0f, ParallaxSteps);
    float currentLayerDepth = 0.0f;
    float layerDepth = 1.0f / numSteps;
    vec2 currentTexCoords = texCoords;
    float currentDepthMapValue = d.depthTex(currentTexCoords);
    vec2 deltaTexCoords = vec2(viewDir.x, viewDir.y) * ParallaxHeightScale / (viewDir.z * numSteps);
    for (float i = 0.0f; i < numSteps; i++) {
        if (currentLayerDepth < currentDepthMapValue) {
            currentTexCoords -= deltaTexCoords;
            currentDepthMapValue = d.depthTex(currentTexCoords);
            currentLayerDepth += layerDepth;
        } else {
            break;
        }
    }
    if (!runTail) return currentTexCoords;
    vec2 prevTexCoords = currentTexCoords + deltaTexCoords;
    float afterDepth = currentDepthMapValue - currentLayerDepth;
    float beforeDepth = d.depthTex(prevTexCoords) - currentLayerDepth + layerDepth;
    float weight = afterDepth / (afterDepth - beforeDepth);
    return prevTexCoords * weight + currentTexCoords * (1.0f - weight);
}

// LearnOpenGL's steep parallax and parallax occlusion listings (LearnOpenGL, min 8 / max 32 layers
// mixed by |V.z|; the stored copy of LearnOpenGL stops before them, the deferred-renderer blog
// repeats the structure; docs/model.md §6b pins the same loop). P = viewDir.xy / viewDir.z *
// height_scale; delta = P / numLayers.
vec2 learnOpenGLSteep(const Doc& d, vec2 texCoords, vec3 viewDir, float height_scale, bool pom) {
    const float minLayers = 8.0f, maxLayers = 32.0f;
    float a = std::fabs(viewDir.z);
    float numLayers = maxLayers * (1.0f - a) + minLayers * a;  // mix()
    float layerDepth = 1.0f / numLayers;
    float currentLayerDepth = 0.0f;
    vec2 P = vec2(viewDir.x, viewDir.y) / viewDir.z * height_scale;
    vec2 deltaTexCoords = P / numLayers;
    vec2 currentTexCoords = texCoords;
    float currentDepthMapValue = d.depthTex(currentTexCoords);
    while (currentLayerDepth < currentDepthMapValue) {
        currentTexCoords -= deltaTexCoords;
        currentDepthMapValue = d.depthTex(currentTexCoords);
        currentLayerDepth += layerDepth;
    }
    if (!pom) return currentTexCoords;
    vec2 prevTexCoords = currentTexCoords + deltaTexCoords;
    float afterDepth = currentDepthMapValue - currentLayerDepth;
    float beforeDepth = d.depthTex(prevTexCoords) - currentLayerDepth + layerDepth;
    float weight = afterDepth / (afterDepth - beforeDepth);
    return prevTexCoords * weight + currentTexCoords * (1.0f - weight);
}

// Lengyel FGED 2 Listing 7.9 on a parallax map built as Lengyel FGED 2 says: per texel n_z * (2h -
// 1) with n from Eq. 7.41-7.43 at a height scale sTex in texels; scale = (sTex / (2 k r_x), sTex /
// (2 k r_y)) (Eq. 7.52), k = 4.
struct LengyelMaps {
    Texture parallaxMap;  // n_z (2h - 1)
    Texture normalMap;    // n
};
LengyelMaps lengyelMaps(const Texture& h, double sTex) {
    LengyelMaps m;
    m.parallaxMap = h;
    m.normalMap = h;
    m.normalMap.channels = 3;
    m.normalMap.texels.assign(h.texels.size() * 3, 0.f);
    const int W = h.width, H = h.height;
    for (int j = 0; j < H; ++j)
        for (int i = 0; i < W; ++i) {
            // Eq. 7.41 with wrapped neighbours (Listing 7.5 wraps around).
            double dx = sTex / 2 * (h.texel((i + 1) % W, j) - h.texel((i + W - 1) % W, j));
            double dy = sTex / 2 * (h.texel(i, (j + 1) % H) - h.texel(i, (j + H - 1) % H));
            double inv = 1 / std::sqrt(dx * dx + dy * dy + 1);  // Eq. 7.43
            m.normalMap.texel(i, j, 0) = float(-dx * inv);
            m.normalMap.texel(i, j, 1) = float(-dy * inv);
            m.normalMap.texel(i, j, 2) = float(inv);
            m.parallaxMap.texel(i, j) = float(inv * (2 * h.texel(i, j) - 1));
        }
    return m;
}

vec2 applyParallaxOffset(const Texture& parallaxMap, vec2 texcoord, vec3 vdir, vec2 scale) {
    vec2 pdir = vec2(vdir.x, vdir.y) * scale;
    for (int i = 0; i < 4; i++) {
        float parallax = sampleBilinear<float>(parallaxMap, texcoord);
        texcoord += pdir * parallax;
    }
    return texcoord;
}

struct Case {
    Vec2f uv0;
    Vec3f v;
};

std::vector<Case> randomCases(int n, double maxTheta, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    std::vector<Case> cases;
    for (int k = 0; k < n; ++k)
        cases.push_back({Vec2f(float(uni(rng)), float(uni(rng))),
                         Vec3f(viewFromAngles(maxTheta * uni(rng), 360 * uni(rng)))});
    return cases;
}

Vec2f ours(const MethodConfig& cfg, const MethodTextures& tex, Case c) {
    MethodContext<float> ctx = makeMethodContext<float>(tex);
    return runMethod<float>(*cfg.builtin(), ctx, c.uv0, c.v);
}

class Documents : public ::testing::Test {
  protected:
    Texture height = test::makeTexture(48, 48, [](int i, int j) {
        double u = (i + 0.5) / 48, v = (j + 0.5) / 48;
        return 0.5 + 0.3 * std::sin(2 * kPi * 2 * u) * std::cos(2 * kPi * 3 * v) +
               0.15 * std::sin(2 * kPi * 5 * (u + v));
    });
    Doc doc{&height};
};

// Welsh's constants 0.04, -0.02 are s = 0.04, b = -0.02 (docs/model.md §3).
TEST_F(Documents, WelshParallaxAndOffsetLimiting) {
    MethodTextures tex = makeMethodTextures(height, 0.04, -0.02, 1.0, false);
    for (const Case& c : randomCases(500, 80, 1)) {
        Vec2f a = ours(test::method(R"({"name":"parallax"})"), tex, c);
        Vec2f b = welshParallax(doc, c.uv0, c.v);
        EXPECT_EQ(a.x, b.x);  // same operations in the same order: bit-identical
        EXPECT_EQ(a.y, b.y);
        Vec2f a2 = ours(test::method(R"({"name":"offset_limited"})"), tex, c);
        Vec2f b2 = welshOffsetLimited(doc, c.uv0, c.v);
        EXPECT_EQ(a2.x, b2.x);
        EXPECT_EQ(a2.y, b2.y);
    }
}

// LearnOpenGL's depth form with height_scale k is s = k, b = -k. Different order of float
// operations: agreement to a few ulps of the offset.
TEST_F(Documents, LearnOpenGLParallaxDepthForm) {
    const float k = 0.1f;
    MethodTextures tex = makeMethodTextures(height, k, -k, 1.0, false);
    for (const Case& c : randomCases(500, 80, 2)) {
        Vec2f a = ours(test::method(R"({"name":"parallax"})"), tex, c);
        Vec2f b = learnOpenGLParallax(doc, c.uv0, c.v, k);
        float tol = 4e-7f * (1.0f + std::fabs(c.v.x / c.v.z) + std::fabs(c.v.y / c.v.z));
        EXPECT_NEAR(a.x, b.x, tol) << "uv0 " << c.uv0.x << "," << c.uv0.y;
        EXPECT_NEAR(a.y, b.y, tol);
    }
}

// LearnOpenGL's steep and POM listings: our steep/pom (min 8, max 32) at s = k, b = -k run
// the same float operations, so they agree bit for bit, fetch for fetch.
TEST_F(Documents, LearnOpenGLSteepAndPomBitIdentical) {
    const float k = 0.1f;
    MethodTextures tex = makeMethodTextures(height, k, -k, 1.0, false);
    for (const Case& c : randomCases(2000, 85, 3)) {
        Vec2f s = ours(test::method(R"({"name":"steep","min_layers":8,"max_layers":32})"), tex, c);
        Vec2f sd = learnOpenGLSteep(doc, c.uv0, c.v, k, false);
        ASSERT_EQ(s.x, sd.x) << "uv0 " << c.uv0.x << "," << c.uv0.y << " V.z " << c.v.z;
        ASSERT_EQ(s.y, sd.y);
        Vec2f p = ours(test::method(R"({"name":"pom","min_layers":8,"max_layers":32})"), tex, c);
        Vec2f pd = learnOpenGLSteep(doc, c.uv0, c.v, k, true);
        ASSERT_EQ(p.x, pd.x) << "uv0 " << c.uv0.x << "," << c.uv0.y << " V.z " << c.v.z;
        ASSERT_EQ(p.y, pd.y);
    }
}

// the deferred-renderer blog: 100 fixed layers and a 100-step loop at height scale 0.15 = steep
// with layers 100, max_steps 100, s = 0.15, b = -0.15. the deferred-renderer blog forms the step as
// V.xy * s / (V.z * n), we as V.xy / V.z * s / n: the steps differ in the last bit, so a step count
// can flip where the ray grazes a layer boundary. Such flips are counted and must stay rare.
TEST_F(Documents, DeferredBlogSteepAndItsPomTail) {
    MethodTextures tex = makeMethodTextures(height, 0.15, -0.15, 1.0, false);
    MethodConfig steep = test::method(R"({"name":"steep","layers":100,"max_steps":100})");
    MethodConfig pom = test::method(R"({"name":"pom","layers":100,"max_steps":100})");
    int flips = 0, n = 2000;
    for (const Case& c : randomCases(n, 80, 4)) {
        Vec2f a = ours(steep, tex, c), b = deferredBlogSteep(doc, c.uv0, c.v, false);
        Vec2f p = ours(pom, tex, c), q = deferredBlogSteep(doc, c.uv0, c.v, true);
        // Same step count: equal to float rounding of 100 accumulated steps.
        bool same = std::fabs(a.x - b.x) < 2e-5f && std::fabs(a.y - b.y) < 2e-5f;
        if (!same) {
            ++flips;
            continue;
        }
        EXPECT_NEAR(p.x, q.x, 1e-4f) << "uv0 " << c.uv0.x << "," << c.uv0.y;
        EXPECT_NEAR(p.y, q.y, 1e-4f);
    }
    EXPECT_LE(flips, n / 200) << flips << " step-count flips of " << n;
}

// Lengyel FGED 2 Listing 7.9 with k = 4 and Eq. 7.52's scale: our iterative at b = -s/2 (Lengyel
// FGED 2's signed height 2h - 1). sTex = s * W is Lengyel FGED 2's scale in texels (square map).
TEST_F(Documents, LengyelIterativeListing) {
    const double s = 0.05;
    const int k = 4;
    LengyelMaps lm = lengyelMaps(height, s * height.width);
    Vec2f scale(float(s * height.width / (2.0 * k * height.width)),
                float(s * height.height / (2.0 * k * height.height)));
    MethodTextures tex = makeMethodTextures(height, s, -s / 2, 1.0, true);
    for (const Case& c : randomCases(500, 80, 5)) {
        Vec2f a = ours(test::method(R"({"name":"iterative","iterations":4})"), tex, c);
        Vec2f b = applyParallaxOffset(lm.parallaxMap, c.uv0, c.v, scale);
        EXPECT_NEAR(a.x, b.x, 2e-6f) << "uv0 " << c.uv0.x << "," << c.uv0.y;
        EXPECT_NEAR(a.y, b.y, 2e-6f);
    }
}

// Lengyel FGED 2 Eq. 7.48-7.50: the point n_z h / dot(n, v) * v, with h the signed height in UV
// units (s * (h - 1/2)), at texel centres where bilinear sampling returns the texel itself.
TEST_F(Documents, LengyelTangentPlaneEquation) {
    const double s = 0.05;
    LengyelMaps lm = lengyelMaps(height, s * height.width);
    MethodTextures tex = makeMethodTextures(height, s, -s / 2, 1.0, true);
    std::mt19937 rng(6);
    std::uniform_int_distribution<int> texel(0, 47);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    for (int n = 0; n < 500; ++n) {
        int i = texel(rng), j = texel(rng);
        Vec3d v = viewFromAngles(70 * uni(rng), 360 * uni(rng));
        Vec3d nrm(lm.normalMap.texel(i, j, 0), lm.normalMap.texel(i, j, 1),
                  lm.normalMap.texel(i, j, 2));
        nrm = glm::normalize(nrm);
        double hSigned = s * (height.texel(i, j) - 0.5);
        Vec2d uv0((i + 0.5) / 48, (j + 0.5) / 48);
        Vec2d want = uv0 + Vec2d(v.x, v.y) * (nrm.z * hSigned / glm::dot(nrm, v));
        Vec2f a = ours(test::method(R"({"name":"tangent_plane"})"), tex, {Vec2f(uv0), Vec3f(v)});
        EXPECT_NEAR(a.x, want.x, 3e-6) << "texel " << i << "," << j;
        EXPECT_NEAR(a.y, want.y, 3e-6) << "texel " << i << "," << j;
    }
}

}  // namespace
}  // namespace pgt
