// The method-kind table (methods/registry.h) and the dispatch through it.
#include "methods/registry.h"

#include <type_traits>

#include "core/error.h"
#include "methods/builtin/cone.h"
#include "methods/builtin/layered.h"
#include "methods/builtin/lengyel.h"
#include "methods/builtin/maxmip.h"
#include "methods/builtin/refined.h"
#include "methods/builtin/simple.h"
#include "methods/builtin/slope.h"

namespace pgt {

namespace {

// A layer or step count above this is no longer a shading setting (LearnOpenGL uses 8-32,
// the deferred-renderer blog uses 100); it bounds a typo before it costs minutes per frame.
constexpr int kMaxLayers = 4096;

// Steep and pom: "32" when the layer count is fixed, "8_32" for a range, "_s100" with a cap.
std::string layerLabel(const BuiltinMethod& m) {
    const auto& c = m.as<LayerParameters>();
    std::string s = c.minLayers == c.maxLayers
                        ? std::to_string(c.maxLayers)
                        : std::to_string(c.minLayers) + "_" + std::to_string(c.maxLayers);
    if (c.maxSteps) s += "_s" + std::to_string(c.maxSteps);
    return s;
}

// Any other kind's label: its written parameters' values in its row's order, joined by "_"
// (relief "10_5", cone "32_5", iterative "4").
std::string parameterValues(const BuiltinMethod& m) {
    std::string s;
    for (const IntParameter& p : kindInfo(m.kind).parameters) {
        if (!p.written) continue;
        if (!s.empty()) s += '_';
        s += std::to_string(p.get(m));
    }
    return s;
}

using L = LayerParameters;
const std::vector<IntParameter> kLayerParameters = {
    intParameter<L, &L::minLayers>("min_layers", 1, kMaxLayers),
    intParameter<L, &L::maxLayers>("max_layers", 1, kMaxLayers),
    // A fixed layer count: min = max. Read after the two above, so it wins.
    intParameter<L, &L::minLayers, &L::maxLayers>("layers", 1, kMaxLayers, false),
    intParameter<L, &L::maxSteps>("max_steps", 0, kSafetyStepCap),
};

const std::vector<IntParameter> kReliefParameters = {
    intParameter<ReliefParameters, &ReliefParameters::linearSteps>("linear_steps", 1, kMaxLayers),
    // 64 halvings: past a double's precision
    intParameter<ReliefParameters, &ReliefParameters::binarySteps>("binary_steps", 0, 64),
};

const std::vector<IntParameter> kSecantParameters = {
    intParameter<SecantParameters, &SecantParameters::linearSteps>("linear_steps", 1, kMaxLayers),
    intParameter<SecantParameters, &SecantParameters::secantSteps>("secant_steps", 0, 64),
};

const std::vector<IntParameter> kContactParameters = {
    intParameter<ContactParameters, &ContactParameters::layers>("layers", 1, kMaxLayers),
};

const std::vector<IntParameter> kMaxMipParameters = {
    intParameter<MaxMipParameters, &MaxMipParameters::maxIterations>("max_iterations", 1, 1 << 24),
};

const std::vector<IntParameter> kConeParameters = {
    intParameter<ConeParameters, &ConeParameters::steps>("steps", 0, kMaxLayers),
    intParameter<ConeParameters, &ConeParameters::refineSteps>("refine_steps", 0, 64),
};

using R = RelaxedConeParameters;
const std::vector<IntParameter> kRelaxedConeParameters = {
    intParameter<R, &R::coneSteps>("cone_steps", 0, kMaxLayers),
    intParameter<R, &R::binarySteps>("binary_steps", 0, 64),
};

const std::vector<IntParameter> kIterativeParameters = {
    intParameter<IterationParameters, &IterationParameters::iterations>("iterations", 1, 1024),
};

}  // namespace

namespace {

using K = MethodKind;
using M = MapKind;

// The table: one row per built-in kind, in MethodKind order (a namespace-scope object: read
// through methodKinds() from functions only, never during another file's static initialisation).
const std::vector<MethodKindInfo> kMethodKinds = {
    {.name = "none",
     .kind = K::None,
     .summary = "no parallax: uv' = uv0, the normal-mapping baseline",
     .cite = "",
     .runFloat = methodNone<float>,
     .runDouble = methodNone<double>,
     .twin = {.file = "none.glsl", .function = "ParallaxNone", .scaleBias = false}},
    {.name = "parallax",
     .kind = K::Parallax,
     .summary = "one offset along V.xy / V.z by the height at uv0",
     .cite = "welsh2004 kaneko2001",
     .runFloat = methodParallax<float>,
     .runDouble = methodParallax<double>,
     .maps = {M::Height},
     .twin = {.file = "parallax.glsl", .function = "ParallaxMapping", .maps = {M::Height}}},
    {.name = "offset_limited",
     .kind = K::OffsetLimited,
     .summary = "parallax without the division by V.z",
     .cite = "welsh2004",
     .runFloat = methodOffsetLimited<float>,
     .runDouble = methodOffsetLimited<double>,
     .maps = {M::Height},
     .twin = {.file = "offset_limited.glsl", .function = "OffsetLimited", .maps = {M::Height}}},
    {.name = "steep",
     .kind = K::Steep,
     .summary = "march of equal depth layers, layer count mixed by V.z; stops below the surface",
     .cite = "mcguire2005 devries2020 deferredblog2025",
     .defaults = LayerParameters{},
     .parameters = kLayerParameters,
     .stepKey = "layers",
     .labelParameters = layerLabel,
     .runFloat = methodSteep<float>,
     .runDouble = methodSteep<double>,
     .maps = {M::Height},
     .twin = {.file = "layered.glsl",
              .function = "SteepParallax",
              .maps = {M::Height},
              .floatParameters = {"min_layers", "max_layers"},
              .marches = true}},
    {.name = "pom",
     .kind = K::Pom,
     .summary = "steep's march, then the line through its last two samples meets the ray",
     .cite = "brawley2004 tatarchuk2006 devries2020",
     .defaults = LayerParameters{},
     .parameters = kLayerParameters,
     .stepKey = "layers",
     .labelParameters = layerLabel,
     .runFloat = methodPom<float>,
     .runDouble = methodPom<double>,
     .maps = {M::Height},
     .twin = {.file = "layered.glsl",
              .function = "ParallaxOcclusion",
              .maps = {M::Height},
              .floatParameters = {"min_layers", "max_layers"},
              .marches = true}},
    {.name = "relief",
     .kind = K::Relief,
     .summary = "linear search, then binary search of the bracket",
     .cite = "policarpo2005",
     .defaults = ReliefParameters{},
     .parameters = kReliefParameters,
     .stepKey = "linear_steps",
     .labelParameters = parameterValues,
     .runFloat = methodRelief<float>,
     .runDouble = methodRelief<double>,
     .maps = {M::Height},
     .twin = {.file = "relief.glsl",
              .function = "ReliefMapping",
              .maps = {M::Height},
              .marches = true}},
    {.name = "iterative",
     .kind = K::Iterative,
     .summary = "k equal steps along V.xy by the parallax map P = m_z (s h + b)",
     .cite = "lengyel2019",
     .defaults = IterationParameters{},
     .parameters = kIterativeParameters,
     .stepKey = "iterations",
     .labelParameters = parameterValues,
     .runFloat = methodIterative<float>,
     .runDouble = methodIterative<double>,
     .maps = {M::Height, M::Normal, M::Parallax},
     .twin = {.file = "lengyel.glsl",
              .function = "IterativeParallax",
              .maps = {M::Parallax},
              .scaleBias = false}},
    {.name = "tangent_plane",
     .kind = K::TangentPlane,
     .summary = "the eye ray meets the tangent plane at uv0 (the normal map's slope)",
     .cite = "lengyel2019",
     .runFloat = methodTangentPlane<float>,
     .runDouble = methodTangentPlane<double>,
     .maps = {M::Height, M::Normal, M::Parallax},
     .twin = {.file = "lengyel.glsl",
              .function = "TangentPlaneParallax",
              .maps = {M::Normal, M::Parallax},
              .scaleBias = false}},
    {.name = "secant",
     .kind = K::Secant,
     .summary = "relief's linear search, then secant steps in the bracket",
     .cite = "risser2007",
     .defaults = SecantParameters{},
     .parameters = kSecantParameters,
     .stepKey = "linear_steps",
     .labelParameters = parameterValues,
     .runFloat = methodSecant<float>,
     .runDouble = methodSecant<double>,
     .maps = {M::Height},
     .twin = {.file = "refined.glsl",
              .function = "SecantRelief",
              .maps = {M::Height},
              .marches = true}},
    {.name = "contact",
     .kind = K::Contact,
     .summary = "a coarse march, one step back, a fine march inside it, pom's interpolation",
     .cite = "riccardi2018",
     .defaults = ContactParameters{},
     .parameters = kContactParameters,
     .stepKey = "layers",
     .labelParameters = parameterValues,
     .runFloat = methodContact<float>,
     .runDouble = methodContact<double>,
     .maps = {M::Height},
     .twin = {.file = "refined.glsl",
              .function = "ContactRefinement",
              .maps = {M::Height},
              .marches = true}},
    {.name = "maxmip",
     .kind = K::MaxMip,
     .summary = "exact first crossing with the bilinear surface over a min-max pyramid",
     .cite = "tevs2008",
     .defaults = MaxMipParameters{},
     .parameters = kMaxMipParameters,
     .runFloat = methodMaxMip<float>,
     .runDouble = methodMaxMip<double>,
     .maps = {M::Height, M::Pyramid},
     .twin = {.file = "maxmip.glsl",
              .function = "MaxMipTrace",
              .maps = {M::Height, M::Pyramid},
              .marches = true}},
    {.name = "cone",
     .kind = K::Cone,
     .summary = "cone step mapping on a conservative cone map, then bisections",
     .cite = "dummer2006",
     .defaults = ConeParameters{},
     .parameters = kConeParameters,
     .stepKey = "steps",
     .labelParameters = parameterValues,
     .runFloat = methodCone<float>,
     .runDouble = methodCone<double>,
     .maps = {M::Height, M::Cone},
     .twin = {.file = "cone.glsl",
              .function = "ConeStep",
              .maps = {M::Height, M::Cone},
              .marches = true}},
    {.name = "relaxed_cone",
     .kind = K::RelaxedCone,
     .summary = "relaxed cone stepping, then binary steps",
     .cite = "policarpo2007",
     .defaults = RelaxedConeParameters{},
     .parameters = kRelaxedConeParameters,
     .stepKey = "cone_steps",
     .labelParameters = parameterValues,
     .runFloat = methodRelaxedCone<float>,
     .runDouble = methodRelaxedCone<double>,
     .maps = {M::Height, M::RelaxedCone},
     .twin = {.file = "cone.glsl",
              .function = "RelaxedConeStep",
              .maps = {M::Height, M::RelaxedCone},
              .marches = true}},
    {.name = "iterative_slope",
     .kind = K::IterativeSlope,
     .summary = "the ray point climbs k times toward the tangent plane at its own uv",
     .cite = "premecz2006 szirmaykalos2008",
     .defaults = IterationParameters{},
     .parameters = kIterativeParameters,
     .stepKey = "iterations",
     .labelParameters = parameterValues,
     .runFloat = methodIterativeSlope<float>,
     .runDouble = methodIterativeSlope<double>,
     .maps = {M::Height, M::Normal},
     .twin = {.file = "slope.glsl",
              .function = "IterativeSlopeParallax",
              .maps = {M::Height, M::Normal}}},
};

}  // namespace

const std::vector<MethodKindInfo>& methodKinds() {
    static const std::vector<MethodKindInfo>& kinds = kMethodKinds;
    // kindInfo indexes the table by enum value: checked once here, not per fragment.
    static const bool inOrder = [] {
        for (size_t i = 0; i < kinds.size(); ++i) PGT_CHECK(size_t(kinds[i].kind) == i);
        return true;
    }();
    (void)inOrder;
    return kinds;
}

const MethodKindInfo& kindInfo(MethodKind kind) {
    const auto& kinds = methodKinds();
    PGT_CHECK_LT(size_t(kind), kinds.size());
    return kinds[size_t(kind)];
}

std::string toString(MethodKind kind) { return kindInfo(kind).name; }

const std::vector<std::string>& methodNames() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> n;
        for (const auto& k : methodKinds()) n.push_back(k.name);
        return n;
    }();
    return names;
}

BuiltinMethod builtinOf(MethodKind kind) {
    return BuiltinMethod{.kind = kind, .parameters = kindInfo(kind).defaults};
}

bool setBuiltinStepCount(BuiltinMethod& m, int steps) {
    const MethodKindInfo& info = kindInfo(m.kind);
    if (!info.stepKey) return false;
    for (const IntParameter& p : info.parameters) {
        if (std::string(p.key) != info.stepKey) continue;
        p.set(m, steps);
        return true;
    }
    return false;
}

template <class Real>
Vec2<Real> runMethod(const BuiltinMethod& m, MethodContext<Real>& ctx, Vec2<Real> uv0,
                     Vec3<Real> v) {
    const MethodKindInfo& info = kindInfo(m.kind);
    ctx.gpu8 = m.gpu8Filter;
    if constexpr (std::is_same_v<Real, float>)
        return info.runFloat(ctx, uv0, v, m);
    else
        return info.runDouble(ctx, uv0, v, m);
}

template Vec2<float> runMethod<float>(const BuiltinMethod&, MethodContext<float>&, Vec2<float>,
                                      Vec3<float>);
template Vec2<double> runMethod<double>(const BuiltinMethod&, MethodContext<double>&, Vec2<double>,
                                        Vec3<double>);

}  // namespace pgt
