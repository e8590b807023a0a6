// The method kinds in one table: each kind's scene name, its integer parameters (scene key,
// range, the configuration field they set), the step count a fit varies, how a generated
// label shows its parameters, whether it reads Lengyel FGED 2's derived maps, and its function. (A
// shader method has no row: methods/shader/glsl_spec.h describes it.)
// Parsing (methods/config.h), labels, JSON, the fit and the dispatch all read this table; a
// new built-in method is one row here and one function in methods/.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "methods/method.h"

namespace pgt {

// One integer parameter of a method kind: a field of its kind's parameter struct
// (methods/method.h), made by intParameter below.
struct IntParameter {
    const char* key;                                // the scene's key: "min_layers"
    int& (*field)(KindParameters&) = nullptr;       // the field it sets
    int (*value)(const KindParameters&) = nullptr;  // and reads
    int& (*alsoField)(KindParameters&) = nullptr;   // a second field set to the same value
    int lo = 1, hi = 1;                             // accepted range
    bool written = true;  // part of the configuration's JSON (an alias like "layers" is not)
    void set(BuiltinMethod& m, int v) const {
        field(m.parameters) = v;
        if (alsoField) alsoField(m.parameters) = v;
    }
    int get(const BuiltinMethod& m) const { return value(m.parameters); }
};
// Parameter `key` of struct P's field F (and G, an alias's second field).
template <class P, int P::*F, int P::*G = nullptr>
IntParameter intParameter(const char* key, int lo, int hi, bool written = true) {
    IntParameter p{key};
    p.field = [](KindParameters& k) -> int& { return std::get<P>(k).*F; };
    p.value = [](const KindParameters& k) { return std::get<P>(k).*F; };
    if constexpr (G != nullptr)
        p.alsoField = [](KindParameters& k) -> int& { return std::get<P>(k).*G; };
    p.lo = lo, p.hi = hi, p.written = written;
    return p;
}

template <class Real>
using MethodFunction = Vec2<Real> (*)(MethodContext<Real>&, Vec2<Real>, Vec3<Real>,
                                      const BuiltinMethod&);

// A built-in's GLSL twin among the shaders shipped with pgt (src/methods/builtin/): what the twin
// test runs against the C++ method and scenes/glsl_twins.json lists (twinEntry writes its
// method entry, methods/config.h).
struct GlslTwin {
    const char* file = nullptr;  // "layered.glsl"; null: no twin (a test fails)
    const char* function = nullptr;
    MapSet maps = {};       // the samplers it declares, named MapKindInfo::twinSampler
    bool scaleBias = true;  // uniforms height_scale, height_bias bound to the case's s and b
    // The parameters its shader declares as float uniforms (layered.glsl mixes the layer
    // counts); the others are int uniforms.
    std::vector<std::string> floatParameters = {};
    // A march: a float comparison that ties may flip a layer against the C++ (the twin test
    // allows 1 % of fragments); otherwise the twin agrees with the C++ everywhere.
    bool marches = false;
};

struct MethodKindInfo {
    const char* name;
    MethodKind kind;
    const char* summary = "";  // one line: what it computes (`pgt methods`)
    const char* cite = "";     // its sources' keys in docs/references.md, space-separated
    KindParameters defaults = NoParameters{};   // its parameter struct at the sources' settings
    std::vector<IntParameter> parameters = {};  // the scene's keys of its fields
    const char* stepKey = nullptr;              // the key of `parameters` a fit varies, or null
    // The parameters shown in a generated label ("8_32" for pom), "" when there are none.
    std::string (*labelParameters)(const BuiltinMethod&) = nullptr;
    MethodFunction<float> runFloat = nullptr;
    MethodFunction<double> runDouble = nullptr;
    MapSet maps = {};  // the maps it reads (methods/maps.h)
    GlslTwin twin = {};
};

// Every built-in kind, in MethodKind order.
const std::vector<MethodKindInfo>& methodKinds();
// The row of a built-in kind.
const MethodKindInfo& kindInfo(MethodKind kind);
// A built-in of `kind` at its row's defaults.
BuiltinMethod builtinOf(MethodKind kind);
// The parameter a fit varies set to `steps` (every field it sets); false when the kind has none.
bool setBuiltinStepCount(BuiltinMethod& m, int steps);

// Runs one built-in on one fragment. Never throws; stiff cases land in ctx.flags.
template <class Real>
Vec2<Real> runMethod(const BuiltinMethod& m, MethodContext<Real>& ctx, Vec2<Real> uv0,
                     Vec3<Real> viewTangent);

extern template Vec2<float> runMethod<float>(const BuiltinMethod&, MethodContext<float>&,
                                             Vec2<float>, Vec3<float>);
extern template Vec2<double> runMethod<double>(const BuiltinMethod&, MethodContext<double>&,
                                               Vec2<double>, Vec3<double>);

}  // namespace pgt
