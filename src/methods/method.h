// The common signature of every parallax method (docs/model.md §6b) and the configuration a scene
// gives it. Methods are pure functions templated on the scalar: float by default (as a GPU
// computes), double with `precision: double`. They read textures only through
// MethodContext, which counts fetches (docs/model.md §8) and never throw: stiff cases are flagged.
#pragma once

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "core/math.h"
#include "heightfield/texture.h"
#include "methods/maps.h"

namespace pgt {

// The built-in methods (docs/model.md §6b; methods/registry.h has a row for each).
enum class MethodKind {
    None,
    Parallax,
    OffsetLimited,
    Steep,
    Pom,
    Relief,
    Iterative,
    TangentPlane,
    Secant,
    Contact,
    MaxMip,
    Cone,
    RelaxedCone,
    IterativeSlope
};

struct GlslSpec;  // methods/shader/glsl_spec.h: a user's shader function run in OpenGL

// The self-shadowing a method does toward the view's light (docs/model.md §6c): none, the
// hard march of the POM literature, or Tatarchuk's soft shadow (DirectX SDK sample).
enum class ShadowMarch { None, Hard, Soft };

// Each kind's own parameters, their defaults written once here (the sources' own settings);
// methods/registry.cpp's row of a kind names its struct and its keys.
struct NoParameters {};
struct LayerParameters {  // steep, pom (LearnOpenGL's defaults)
    int minLayers = 8, maxLayers = 32;
    int maxSteps = 0;  // 0 = unbounded (LearnOpenGL); the deferred-renderer blog uses 100
};
struct ReliefParameters {  // relief (Policarpo et al. 2005)
    int linearSteps = 10, binarySteps = 5;
};
struct IterationParameters {  // iterative (Lengyel FGED 2 Listing 7.9), iterative_slope (Premecz)
    int iterations = 4;
};
struct SecantParameters {  // secant (Risser et al. 2007)
    int linearSteps = 10, secantSteps = 3;
};
struct ContactParameters {  // contact (Riccardi 2018): one layer count for both marches
    int layers = 16;
};
struct MaxMipParameters {  // maxmip: nodes visited at most (a safety bound)
    int maxIterations = 4096;
};
struct ConeParameters {  // cone (Dummer 2006): cone steps, then pgt's bisections
    int steps = 32, refineSteps = 5;
};
struct RelaxedConeParameters {  // relaxed_cone (Policarpo & Oliveira 2007, listing 18-3)
    int coneSteps = 15, binarySteps = 6;
};
using KindParameters = std::variant<NoParameters, LayerParameters, ReliefParameters,
                                    IterationParameters, SecantParameters, ContactParameters,
                                    MaxMipParameters, ConeParameters, RelaxedConeParameters>;

// A built-in method: its kind, its kind's parameters, and what every built-in reads
// (precision, filter and shadow march). Its C++ function is its kind's row of
// methods/registry.h; registry.h's builtinOf makes one at its kind's defaults.
struct BuiltinMethod {
    MethodKind kind = MethodKind::None;
    KindParameters parameters;
    // The kind's parameters (std::get: a kind reads only its own struct).
    template <class P>
    const P& as() const {
        return std::get<P>(parameters);
    }
    template <class P>
    P& as() {
        return std::get<P>(parameters);
    }
    bool doublePrecision = false;  // rerun in 64-bit to separate rounding from the algorithm
    bool gpu8Filter = false;       // "filter": "gpu8": bilinear weights of 8 fractional bits
    // Self-shadowing, run after the method from the point it found when the view has a light.
    ShadowMarch shadow = ShadowMarch::Hard;
    int shadowSteps = 16;           // the hard march's samples toward the light
    double shadowSoftening = 0.58;  // the soft shadow's g_fShadowSoftening
};

// A shader run in OpenGL: a user's GLSL or HLSL file, or an engine preset's GLSL
// (methods/shader/glsl_spec.h: its text, function, samplers and uniforms). Configurations share
// no spec: a varied one gets a copy.
struct ShaderMethod {
    std::shared_ptr<const GlslSpec> spec;
};

// How an engine stores the height map the method reads (`"format"`): 32-bit float (pgt's
// authored map), or normalised 16- or 8-bit integers, each texel rounded to the nearest of
// 2^n - 1 steps over [0, 1] as a texture upload rounds it, mip levels made from the rounded
// level 0 and rounded again. The truth always runs on the authored map.
enum class StorageFormat { Float, Unorm16, Unorm8 };
inline const char* storageFormatName(StorageFormat f) {
    return f == StorageFormat::Float ? "float" : f == StorageFormat::Unorm16 ? "unorm16" : "unorm8";
}

// One method as a scene lists it: what every method has (its name, label, own (s, b), the
// preset it came from, discard and level of detail), and the method itself, a built-in or a
// shader. What differs by the two is decided in two places: methods/config.h (parse, JSON,
// labels, parameters a study varies, step counts, maps) and evaluate/evaluate.h (running,
// timing, compiling).
struct MethodConfig {
    std::string name;             // "pom"
    std::string label;            // unique within a scene: "pom" or "pom_32"
    std::string preset;           // the engine/document preset it came from, if any
    bool discardOutside = false;  // LearnOpenGL: discard when uv' leaves [0, tiling]^2
    // "lod": "grad": fetches filter trilinearly at uv0's level of detail (textureGrad with the
    // original uv's derivatives; needs "mipmaps"); "zero" (false): level 0, bilinear.
    bool lodGrad = false;
    // The method's own (s, b) when it differs from the truth's (fitting, mis-set shaders);
    // NaN = use the scene's displacement (docs/model.md §3).
    double scale = NAN, bias = NAN;
    // A preset on the scene's surface whose engine fixes b as a multiple of s (b = this x the
    // method's s: -1 a depth map, -0.5 PlayCanvas, 0 Babylon's offset; docs/methods.md "Engine
    // presets"); NaN: the bias is the scene's, or the method's own `bias`.
    double biasPerScale = NAN;
    // The (s, b) the method runs with, given the view's (docs/model.md §3, UV units).
    std::pair<double, double> scaleBias(double viewScale, double viewBias) const {
        const double s = std::isfinite(scale) ? scale : viewScale;
        const double b = std::isfinite(bias)           ? bias
                         : std::isfinite(biasPerScale) ? biasPerScale * s
                                                       : viewBias;
        return {s, b};
    }
    StorageFormat format = StorageFormat::Float;  // the height map as the method reads it
    // "V": "per_vertex": V computed per vertex and interpolated (FragmentInputs::viewVertex),
    // as jMonkeyEngine and Ogre do; else per pixel.
    bool viewPerVertex = false;
    std::variant<BuiltinMethod, ShaderMethod> method;

    // The built-in (null for a shader), and the shader's spec (null for a built-in).
    const BuiltinMethod* builtin() const { return std::get_if<BuiltinMethod>(&method); }
    BuiltinMethod* builtin() { return std::get_if<BuiltinMethod>(&method); }
    const GlslSpec* shader() const {
        const ShaderMethod* s = std::get_if<ShaderMethod>(&method);
        return s ? s->spec.get() : nullptr;
    }
};

// Stiff-case flags a method raises (counted per frame, never thrown).
enum MethodFlag : uint32_t {
    kFlagZeroDivide = 1u << 0,  // pom's w = 0/0, tangent_plane's dot(n, V) <= 0
    kFlagStepLimit = 1u << 1,   // the march hit max_steps (or the safety cap) before the surface
};

// A march longer than this is a runaway (non-finite or absurd depth values): stop and flag.
inline constexpr int kSafetyStepCap = 1 << 16;

// Texture access for the methods: the maps of methods/maps.h; every sample is one fetch
// (docs/model.md §8).
template <class Real>
struct MethodContext : MapRefs {
    Real scale = 0, bias = 0;  // s, b in UV units (docs/model.md §3)
    int fetches = 0;
    uint32_t flags = 0;
    bool gpu8 = false;  // the GPU's 8-bit filter weights (runMethod sets it from the config)
    // The fragment's level of detail for "lod": "grad" (lodFromGradients of uv0's
    // derivatives); 0 = level 0. The caller sets it, and only where the maps have mipmaps.
    Real lod = 0;
    // Out: the height (UV units, docs/model.md §3's s h + b) of the point the method found,
    // set by every method; its depth offset along the eye ray is -height / V.z (§6c).
    Real foundHeight = Real(NAN);

    Real h(Vec2<Real> uv) {
        ++fetches;
        return sample(*height, uv, 0);
    }
    Real depth(Vec2<Real> uv) { return Real(1) - h(uv); }  // d = 1 - h (LearnOpenGL)
    Real parallaxMap(Vec2<Real> uv) {
        ++fetches;
        return sample(*parallax, uv, 0);
    }
    Vec3<Real> normalMap(Vec2<Real> uv) {
        ++fetches;
        return {sample(*normal, uv, 0), sample(*normal, uv, 1), sample(*normal, uv, 2)};
    }

  private:
    Real sample(const Texture& t, Vec2<Real> uv, int c) const {
        return lod > Real(0) ? sampleTrilinear<Real>(t, uv, lod, c, gpu8)
                             : sampleBilinear<Real>(t, uv, c, gpu8);
    }
};

// GLSL's mix(x, y, a) = x * (1 - a) + y * a.
template <class Real>
inline Real glslMix(Real x, Real y, Real a) {
    return x * (Real(1) - a) + y * a;
}

std::string toString(MethodKind kind);
const std::vector<std::string>& methodNames();

}  // namespace pgt
