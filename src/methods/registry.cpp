// The method-kind table (methods/registry.h) and the dispatch through it.
#include "methods/registry.h"

#include <type_traits>

#include "core/error.h"
#include "methods/cone.h"
#include "methods/glsl_spec.h"
#include "methods/layered.h"
#include "methods/lengyel.h"
#include "methods/maxmip.h"
#include "methods/refined.h"
#include "methods/simple.h"

namespace pgt {

namespace {

// A layer or step count above this is no longer a shading setting (LearnOpenGL uses 8-32,
// 004 uses 100); it bounds a typo before it costs minutes per frame.
constexpr int kMaxLayers = 4096;

// Steep and pom: "32" when the layer count is fixed, "8_32" for a range, "_s100" with a cap.
std::string layerLabel(const MethodConfig& c) {
    std::string s = c.minLayers == c.maxLayers
                        ? std::to_string(c.maxLayers)
                        : std::to_string(c.minLayers) + "_" + std::to_string(c.maxLayers);
    if (c.maxSteps) s += "_s" + std::to_string(c.maxSteps);
    return s;
}

std::string reliefLabel(const MethodConfig& c) {
    return std::to_string(c.linearSteps) + "_" + std::to_string(c.binarySteps);
}

std::string iterativeLabel(const MethodConfig& c) { return std::to_string(c.iterations); }

std::string secantLabel(const MethodConfig& c) {
    return std::to_string(c.linearSteps) + "_" + std::to_string(c.secantSteps);
}

std::string contactLabel(const MethodConfig& c) { return std::to_string(c.minLayers); }

const std::vector<IntParameter> kLayerParameters = {
    {"min_layers", &MethodConfig::minLayers, nullptr, 1, kMaxLayers},
    {"max_layers", &MethodConfig::maxLayers, nullptr, 1, kMaxLayers},
    // A fixed layer count: min = max. Read after the two above, so it wins.
    {"layers", &MethodConfig::minLayers, &MethodConfig::maxLayers, 1, kMaxLayers, false},
    {"max_steps", &MethodConfig::maxSteps, nullptr, 0, kSafetyStepCap},
};

const std::vector<IntParameter> kReliefParameters = {
    {"linear_steps", &MethodConfig::linearSteps, nullptr, 1, kMaxLayers},
    {"binary_steps", &MethodConfig::binarySteps, nullptr, 0, 64},  // 64 halvings: past a double
};

const std::vector<IntParameter> kSecantParameters = {
    {"linear_steps", &MethodConfig::linearSteps, nullptr, 1, kMaxLayers},
    {"secant_steps", &MethodConfig::secantSteps, nullptr, 0, 64},
};

// Contact refinement's one layer count serves both of its marches (Riccardi 2018: 16).
const std::vector<IntParameter> kContactParameters = {
    {"layers", &MethodConfig::minLayers, &MethodConfig::maxLayers, 1, kMaxLayers, true, 16},
};

const std::vector<IntParameter> kMaxMipParameters = {
    {"max_iterations", &MethodConfig::maxIterations, nullptr, 1, 1 << 24},
};

// Dummer's cone step mapping: 32 cone steps; 5 bisections after them (pgt's refinement).
const std::vector<IntParameter> kConeParameters = {
    {"steps", &MethodConfig::coneSteps, nullptr, 0, kMaxLayers, true, 32},
    {"refine_steps", &MethodConfig::binarySteps, nullptr, 0, 64, true, 5},
};

// Policarpo & Oliveira's relaxed cone stepping: 15 cone steps, 6 binary steps (listing 18-3).
const std::vector<IntParameter> kRelaxedConeParameters = {
    {"cone_steps", &MethodConfig::coneSteps, nullptr, 0, kMaxLayers, true, 15},
    {"binary_steps", &MethodConfig::binarySteps, nullptr, 0, 64, true, 6},
};

std::string coneLabel(const MethodConfig& c) {
    return std::to_string(c.coneSteps) + "_" + std::to_string(c.binarySteps);
}

const std::vector<IntParameter> kIterativeParameters = {
    {"iterations", &MethodConfig::iterations, nullptr, 1, 1024},
};

}  // namespace

const std::vector<MethodKindInfo>& methodKinds() {
    using K = MethodKind;
    static const std::vector<MethodKindInfo> kinds = {
        {"none", K::None, {}, nullptr, nullptr, false, methodNone<float>, methodNone<double>},
        {"parallax",
         K::Parallax,
         {},
         nullptr,
         nullptr,
         false,
         methodParallax<float>,
         methodParallax<double>},
        {"offset_limited",
         K::OffsetLimited,
         {},
         nullptr,
         nullptr,
         false,
         methodOffsetLimited<float>,
         methodOffsetLimited<double>},
        {"steep", K::Steep, kLayerParameters, "layers", layerLabel, false, methodSteep<float>,
         methodSteep<double>},
        {"pom", K::Pom, kLayerParameters, "layers", layerLabel, false, methodPom<float>,
         methodPom<double>},
        {"relief", K::Relief, kReliefParameters, "linear_steps", reliefLabel, false,
         methodRelief<float>, methodRelief<double>},
        {"iterative", K::Iterative, kIterativeParameters, "iterations", iterativeLabel, true,
         methodIterative<float>, methodIterative<double>},
        {"tangent_plane",
         K::TangentPlane,
         {},
         nullptr,
         nullptr,
         true,
         methodTangentPlane<float>,
         methodTangentPlane<double>},
        {"secant", K::Secant, kSecantParameters, "linear_steps", secantLabel, false,
         methodSecant<float>, methodSecant<double>},
        {"contact", K::Contact, kContactParameters, "layers", contactLabel, false,
         methodContact<float>, methodContact<double>},
        {"maxmip", K::MaxMip, kMaxMipParameters, nullptr, nullptr, false, methodMaxMip<float>,
         methodMaxMip<double>, true},
        {"cone", K::Cone, kConeParameters, "steps", coneLabel, false, methodCone<float>,
         methodCone<double>, false, true},
        {"relaxed_cone", K::RelaxedCone, kRelaxedConeParameters, "cone_steps", coneLabel, false,
         methodRelaxedCone<float>, methodRelaxedCone<double>, false, true, true},
    };
    // kindInfo indexes the table by enum value: checked once here, not per fragment.
    static const bool inOrder = [] {
        for (size_t i = 0; i < kinds.size(); ++i) PGT_CHECK(size_t(kinds[i].kind) == i);
        return true;
    }();
    (void)inOrder;
    return kinds;
}

const MethodKindInfo* kindInfo(MethodKind kind) {
    const auto& kinds = methodKinds();
    const size_t i = size_t(kind);
    return i < kinds.size() ? &kinds[i] : nullptr;  // Glsl is not in the table
}

std::string toString(MethodKind kind) {
    const MethodKindInfo* info = kindInfo(kind);
    return info ? info->name : "glsl";
}

const std::vector<std::string>& methodNames() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> n;
        for (const auto& k : methodKinds()) n.push_back(k.name);
        return n;
    }();
    return names;
}

bool needsDerivedMaps(MethodKind kind) {
    const MethodKindInfo* info = kindInfo(kind);
    return info && info->derivedMaps;
}

bool needsDerivedMaps(const MethodConfig& cfg) {
    if (cfg.glsl) return !cfg.glsl->normalSampler.empty() || !cfg.glsl->parallaxSampler.empty();
    return needsDerivedMaps(cfg.kind);
}

void applyKindDefaults(MethodConfig& cfg) {
    const MethodKindInfo* info = kindInfo(cfg.kind);
    if (!info) return;
    for (const IntParameter& p : info->parameters) {
        if (!p.byDefault) continue;
        cfg.*p.field = *p.byDefault;
        if (p.alsoField) cfg.*p.alsoField = *p.byDefault;
    }
}

bool needsMinMaxPyramid(const MethodConfig& cfg) {
    if (cfg.glsl) return !cfg.glsl->pyramidSampler.empty();
    const MethodKindInfo* info = kindInfo(cfg.kind);
    return info && info->minMaxPyramid;
}

bool needsConeMap(const MethodConfig& cfg) {
    if (cfg.glsl) return !cfg.glsl->coneSampler.empty() || !cfg.glsl->relaxedConeSampler.empty();
    const MethodKindInfo* info = kindInfo(cfg.kind);
    return info && info->coneMap;
}

bool needsRelaxedConeMap(const MethodConfig& cfg) {
    if (cfg.glsl) return !cfg.glsl->relaxedConeSampler.empty();
    const MethodKindInfo* info = kindInfo(cfg.kind);
    return info && info->relaxedConeMap;
}

bool setStepCount(MethodConfig& cfg, int steps) {
    const MethodKindInfo* info = kindInfo(cfg.kind);
    if (!info || !info->stepKey) return false;
    for (const IntParameter& p : info->parameters) {
        if (std::string(p.key) != info->stepKey) continue;
        cfg.*p.field = steps;
        if (p.alsoField) cfg.*p.alsoField = steps;
        return true;
    }
    return false;
}

template <class Real>
Vec2<Real> runMethod(const MethodConfig& cfg, MethodContext<Real>& ctx, Vec2<Real> uv0,
                     Vec3<Real> v) {
    const MethodKindInfo* info = kindInfo(cfg.kind);
    if (!info) return uv0;  // a GLSL method runs in OpenGL (study/evaluate.cpp), never here
    ctx.gpu8 = cfg.gpu8Filter;
    if constexpr (std::is_same_v<Real, float>)
        return info->runFloat(ctx, uv0, v, cfg);
    else
        return info->runDouble(ctx, uv0, v, cfg);
}

template Vec2<float> runMethod<float>(const MethodConfig&, MethodContext<float>&, Vec2<float>,
                                      Vec3<float>);
template Vec2<double> runMethod<double>(const MethodConfig&, MethodContext<double>&, Vec2<double>,
                                        Vec3<double>);

}  // namespace pgt
