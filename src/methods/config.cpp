// Method entries <-> MethodConfig (methods/config.h).
#include "methods/config.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <map>
#include <set>

#include "core/format.h"
#include "core/json_read.h"
#include "core/overloaded.h"
#include "methods/presets/presets.h"
#include "methods/registry.h"
#include "methods/shader/glsl_spec.h"
#include "methods/shader/shader_config.h"

namespace pgt {

namespace {

const std::vector<std::string>& shadowNames() {
    static const std::vector<std::string> names = {"none", "hard", "soft"};
    return names;
}

// "shadow" and "shadow_steps": the march toward the view's light (docs/model.md §6c).
void readShadowParameters(JsonFields& f, BuiltinMethod& cfg) {
    const std::string& current = shadowNames()[size_t(cfg.shadow)];
    const std::string name = f.choice("shadow", shadowNames(), current);
    cfg.shadow = ShadowMarch(std::find(shadowNames().begin(), shadowNames().end(), name) -
                             shadowNames().begin());
    cfg.shadowSteps = f.integer("shadow_steps", cfg.shadowSteps, 1, 4096);
}

// {"preset": NAME, "amplitude": "scene" | "shipped", "label": optional, "scale", "bias",
// "uniforms": {...}}: the preset's configuration on the scene's surface (or at its shipped
// amplitude, labelled NAME_shipped), labelled NAME, with what the entry overrides
// (setShaderParameter).
MethodConfig parsePreset(const Json& object, const std::string& file, const std::string& path,
                         double worldPerUv) {
    JsonFields f(object, file, path);
    std::vector<std::string> names;
    for (const auto& p : methodPresets()) names.push_back(p.name);
    std::string name = f.choice("preset", names, "");
    const bool shipped = f.choice("amplitude", {"scene", "shipped"}, "scene") == "shipped";
    std::string label = f.string("label", shipped ? name + "_shipped" : name);
    checkLabel(label, file, f.fieldPath("label"));
    MethodConfig cfg;
    for (const auto& p : methodPresets())
        if (p.name == name)
            cfg = presetConfig(p, label, file, f.fieldPath("preset"),
                               shipped ? PresetAmplitude::Shipped : PresetAmplitude::Scene,
                               worldPerUv);
    for (const char* key : {"scale", "bias"})
        if (f.has(key)) setShaderParameter(cfg, key, f.raw(key), file, f.fieldPath(key));
    if (BuiltinMethod* b = cfg.builtin()) readShadowParameters(f, *b);
    const bool perVertex = cfg.viewPerVertex;
    readMethodInputs(f, cfg);
    // "V" against the preset's own: its label says so (godot_pv; jme_pp, whose engine
    // interpolates V per vertex), so that the preset can stand beside itself in a list.
    if (!f.has("label") && cfg.viewPerVertex != perVertex) {
        cfg.label += cfg.viewPerVertex ? "_pv" : "_pp";
        checkLabel(cfg.label, file, f.fieldPath("label"));
    }
    if (f.has("uniforms")) {
        const Json& u = f.raw("uniforms");
        if (!u.is_object()) f.fail("uniforms", "expected an object of name: number or [numbers]");
        for (const auto& [uniform, value] : u.items())
            setShaderParameter(cfg, "uniforms." + uniform, value, file,
                               f.fieldPath("uniforms") + "." + uniform);
    }
    f.finish();
    return cfg;
}

// The parameters of a generated label: a built-in's own and its precision and filter, then
// the level of detail, discard, a built-in's shadow march and (s, b).
std::string parameterSuffix(const MethodConfig& c) {
    std::string s;
    auto add = [&s](const char* part, const std::string& value = "") {
        if (!s.empty()) s += '_';
        s += part;
        s += value;
    };
    const BuiltinMethod* b = c.builtin();
    if (b) {
        const MethodKindInfo& info = kindInfo(b->kind);
        s = info.labelParameters ? info.labelParameters(*b) : "";
        if (b->doublePrecision) add("f64");
        if (b->gpu8Filter) add("gpu8");
    }
    if (c.lodGrad) add("grad");
    if (c.format == StorageFormat::Unorm8) add("u8");
    if (c.format == StorageFormat::Unorm16) add("u16");
    if (c.viewPerVertex) add("pv");
    if (c.discardOutside) add("discard");
    if (b && b->shadow != ShadowMarch::Hard) add("shadow_", shadowNames()[size_t(b->shadow)]);
    if (b && b->shadowSteps != BuiltinMethod{}.shadowSteps)
        add("ss", std::to_string(b->shadowSteps));
    // Numbers as an ostream's default %g shows them.
    if (std::isfinite(c.scale)) add("s", formatNumber(c.scale, 6));
    if (std::isfinite(c.bias)) add("b", formatNumber(c.bias, 6));
    return s;
}

}  // namespace

void readMethodParameters(JsonFields& f, MethodConfig& cfg) {
    BuiltinMethod& b = *cfg.builtin();  // a shader's parameters are setShaderParameter's
    for (const IntParameter& p : kindInfo(b.kind).parameters)
        if (f.has(p.key)) p.set(b, f.integer(p.key, p.lo, p.hi));
    cfg.discardOutside = f.boolean("discard_outside", cfg.discardOutside);
    cfg.scale = f.number("scale", cfg.scale, -kMaxOwnDisplacement, kMaxOwnDisplacement);
    cfg.bias = f.number("bias", cfg.bias, -kMaxOwnDisplacement, kMaxOwnDisplacement);
    b.doublePrecision = f.choice("precision", {"float", "double"},
                                 b.doublePrecision ? "double" : "float") == "double";
    b.gpu8Filter = f.choice("filter", {"exact", "gpu8"}, b.gpu8Filter ? "gpu8" : "exact") == "gpu8";
    cfg.lodGrad = f.choice("lod", {"zero", "grad"}, cfg.lodGrad ? "grad" : "zero") == "grad";
    readMethodInputs(f, cfg);
    readShadowParameters(f, b);
}

void readMethodInputs(JsonFields& f, MethodConfig& cfg) {
    const std::string name =
        f.choice("format", {"float", "unorm16", "unorm8"}, storageFormatName(cfg.format));
    cfg.format = name == "unorm8"    ? StorageFormat::Unorm8
                 : name == "unorm16" ? StorageFormat::Unorm16
                                     : StorageFormat::Float;
    cfg.viewPerVertex = f.choice("V", {"per_pixel", "per_vertex"},
                                 cfg.viewPerVertex ? "per_vertex" : "per_pixel") == "per_vertex";
}

MethodConfig parseMethod(const Json& entry, const std::string& file, const std::string& path,
                         double worldPerUv) {
    Json object = entry.is_string() ? Json{{"name", entry}} : entry;
    if (!object.is_object())
        throw InputError(file, path, shortDump(entry), "expected a method name or object");
    if (object.contains("preset")) return parsePreset(object, file, path, worldPerUv);
    JsonFields f(object, file, path);
    // A shader: its file, or a body alone in a language (no built-in has either key).
    for (const char* key : {"glsl", "hlsl", "body", "language"})
        if (object.contains(key)) return parseShaderMethod(f, file);
    MethodConfig cfg;
    cfg.name = f.choice("name", methodNames(), "");
    for (const auto& k : methodKinds())
        if (cfg.name == k.name) cfg.method = builtinOf(k.kind);
    readMethodParameters(f, cfg);
    cfg.label = f.string("label", "");
    if (f.has("label")) checkLabel(cfg.label, file, f.fieldPath("label"));
    f.finish();
    return cfg;
}

namespace {

// `cfg` appended to `out`, and with `twin` its GLSL twin after it as the method table writes
// the twin's entry (twinEntry: "LABEL_gl"; a built-in without a label of its own lends its
// name), read like any shader entry.
void addMethod(MethodConfig cfg, bool twin, const std::string& file, const std::string& at,
               double worldPerUv, std::vector<MethodConfig>& out) {
    out.push_back(cfg);
    if (!twin) return;
    if (!cfg.builtin() || !kindInfo(cfg.builtin()->kind).twin.file)
        throw InputError(file, at + ".twin", "true",
                         "only a built-in method has a GLSL twin (a preset or a shader entry "
                         "runs in GL already)");
    if (cfg.label.empty()) cfg.label = cfg.name;
    out.push_back(parseMethod(twinEntry(cfg), file, at, worldPerUv));
}

}  // namespace

std::vector<MethodConfig> parseMethods(const Json& list, const std::string& file,
                                       const std::string& path, double worldPerUv) {
    if (!list.is_array()) throw InputError(file, path, shortDump(list), "expected an array");
    if (list.empty())
        throw InputError(file, path, "[]",
                         "the method list is empty; known methods: " + joinNames(methodNames()));
    std::vector<MethodConfig> out;
    for (size_t i = 0; i < list.size(); ++i) {
        const std::string at = path + "[" + std::to_string(i) + "]";
        const Json& entry = list[i];
        if (entry.is_object() && entry.contains("builtins")) {  // every built-in, in table order
            JsonFields f(entry, file, at);
            f.choice("builtins", {"all"}, "");
            const bool twins = f.boolean("twins", false);
            f.finish();
            for (const MethodKindInfo& kind : methodKinds())
                addMethod(parseMethod(Json(kind.name), file, at, worldPerUv), twins, file, at,
                          worldPerUv, out);
            continue;
        }
        // "twin": true on a built-in's entry: the entry, then its GLSL twin.
        Json own = entry;
        bool twin = false;
        if (entry.is_object() && entry.contains("twin")) {
            if (!entry.at("twin").is_boolean())
                throw InputError(file, at + ".twin", shortDump(entry.at("twin")),
                                 "expected true or false");
            twin = entry.at("twin").get<bool>();
            own.erase("twin");
        }
        addMethod(parseMethod(own, file, at, worldPerUv), twin, file, at, worldPerUv, out);
    }
    assignLabels(out, file, path);
    return out;
}

void assignLabels(std::vector<MethodConfig>& configs, const std::string& file,
                  const std::string& path) {
    std::map<std::string, int> nameCount;
    for (const auto& m : configs) nameCount[m.name]++;
    // Labels name CSV rows, EXR channels and PNG files: user labels are checked where they
    // are written (checkLabel) and must be unique; generated ones are made unique with a
    // counter that skips every label already taken.
    std::set<std::string> taken;
    for (size_t i = 0; i < configs.size(); ++i) {
        if (configs[i].label.empty()) continue;
        if (!taken.insert(configs[i].label).second)
            throw InputError(file, path + "[" + std::to_string(i) + "].label", configs[i].label,
                             "two methods have this label; labels name the rows and files of "
                             "each method and must differ");
    }
    for (auto& m : configs) {
        if (!m.label.empty()) continue;
        std::string label = m.name;
        std::string suffix = parameterSuffix(m);
        if (nameCount[m.name] > 1 && !suffix.empty()) label += "_" + suffix;
        std::string unique = label;
        for (int k = 2; taken.count(unique); ++k) unique = label + "_" + std::to_string(k);
        m.label = unique;
        taken.insert(unique);
    }
}

void checkLabel(const std::string& label, const std::string& file, const std::string& field) {
    bool ok = !label.empty() && label.size() <= kMaxLabelLength;
    for (char c : label)
        ok =
            ok && (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '+');
    if (!ok)
        throw InputError(file, field, label,
                         "a label is 1 to " + std::to_string(kMaxLabelLength) +
                             " characters of A-Z a-z 0-9 _ - + (it names CSV rows, EXR channels "
                             "and files)");
}

namespace {

// A built-in's parameters, precision, filter and shadow march (absent at their defaults:
// older studies keep their identity).
void builtinJson(const BuiltinMethod& b, Json& j) {
    for (const IntParameter& p : kindInfo(b.kind).parameters)
        if (p.written) j[p.key] = p.get(b);
    j["precision"] = b.doublePrecision ? "double" : "float";
    if (b.gpu8Filter) j["filter"] = "gpu8";
    if (b.shadow != ShadowMarch::Hard) j["shadow"] = shadowNames()[size_t(b.shadow)];
    if (b.shadowSteps != BuiltinMethod{}.shadowSteps) j["shadow_steps"] = b.shadowSteps;
}

}  // namespace

Json toJson(const MethodConfig& c) {
    Json j = {{"name", c.name}, {"label", c.label}};
    if (!c.preset.empty()) j["preset"] = c.preset;
    std::visit(Overloaded{[&](const BuiltinMethod& b) { builtinJson(b, j); },
                          [&](const ShaderMethod& m) { shaderJson(*m.spec, j); }},
               c.method);
    j["discard_outside"] = c.discardOutside;
    if (std::isfinite(c.scale)) j["scale"] = c.scale;
    if (std::isfinite(c.bias)) j["bias"] = c.bias;
    if (std::isfinite(c.biasPerScale)) j["bias_per_scale"] = c.biasPerScale;
    if (c.lodGrad) j["lod"] = "grad";
    if (c.format != StorageFormat::Float) j["format"] = storageFormatName(c.format);
    if (c.viewPerVertex) j["V"] = "per_vertex";
    return j;
}

MapSet needs(const MethodConfig& cfg) {
    return std::visit(Overloaded{[](const BuiltinMethod& b) { return kindInfo(b.kind).maps; },
                                 [](const ShaderMethod& m) {
                                     MapSet named;
                                     for (const MapKindInfo& k : kMapKindTable)
                                         if (!m.spec->sampler(k.kind).empty()) named.add(k.kind);
                                     // a packed layout's RGB is the normal map
                                     if (m.spec->packedNormal()) named.add(MapKind::Normal);
                                     return named;
                                 }},
                      cfg.method);
}

bool hasStepCount(const MethodConfig& cfg) {
    MethodConfig probe = cfg;  // a step count is there where one can be set
    return setStepCount(probe, 1);
}

bool setStepCount(MethodConfig& cfg, int steps) {
    if (BuiltinMethod* b = cfg.builtin()) return setBuiltinStepCount(*b, steps);
    const std::string& uniform = cfg.shader()->stepsUniform;  // its "steps_uniform"
    if (uniform.empty()) return false;
    setShaderParameter(cfg, "uniforms." + uniform, steps, "", "steps");
    return true;
}

Fittable fittable(const MethodConfig& cfg) {
    if (!cfg.preset.empty()) return Fittable::Preset;
    return reaches(cfg, "scale") || reaches(cfg, "bias") ? Fittable::Yes : Fittable::ScaleUnused;
}

bool reaches(const MethodConfig& cfg, const std::string& param) {
    const GlslSpec* g = cfg.shader();
    return !g || g->reaches(param);
}

bool readsDisplacement(const MethodConfig& cfg) {
    const BuiltinMethod* b = cfg.builtin();
    return !b || b->kind != MethodKind::None;
}

bool runsInGl(const MethodConfig& cfg) { return cfg.shader() != nullptr; }

bool readsEngineInputs(const MethodConfig& cfg) {
    return cfg.shader() && cfg.shader()->engineInputs;
}

bool variedAsShader(const MethodConfig& cfg) { return runsInGl(cfg) || !cfg.preset.empty(); }

std::string setShaderParameter(MethodConfig& cfg, const std::string& param, const Json& value,
                               const std::string& file, const std::string& field) {
    auto fail = [&](const std::string& message) -> void {
        throw InputError(file, field, shortDump(value), message);
    };
    if (param == "scale" || param == "bias") {
        if (!reaches(cfg, param))
            fail("the method's own " + param + " would not reach the shader of \"" + cfg.label +
                 "\": no uniform is bound to \"" + param + "\" and no call or body names " +
                 (param == "scale" ? "s" : "b") +
                 " (a preset's height scale is its own uniform: set \"uniforms.NAME\", listed in "
                 "docs/methods.md)");
        if (!value.is_number() || !std::isfinite(value.get<double>()) ||
            std::abs(value.get<double>()) > kMaxOwnDisplacement)
            fail("expected a finite number of at most 1e3 in magnitude");
        (param == "scale" ? cfg.scale : cfg.bias) = value.get<double>();
        if (param == "bias") cfg.biasPerScale = NAN;  // the method's own b, whatever its engine's
        return param.substr(0, 1) + formatNumber(value.get<double>(), 6);
    }
    if (param == "format" || param == "V") {  // what it reads, as any method's
        const Json entry = {{param, value}};
        JsonFields one(entry, file, field.substr(0, field.rfind('.')));
        readMethodInputs(one, cfg);
        one.finish();
        return param == "V" ? (cfg.viewPerVertex ? "per_vertex" : "per_pixel")
                            : storageFormatName(cfg.format);
    }
    const std::string prefix = "uniforms.";
    if (param.rfind(prefix, 0) != 0 || param.size() == prefix.size())
        fail(
            "a GLSL/HLSL method or preset varies \"scale\", \"bias\", \"format\", \"V\" or "
            "\"uniforms.NAME\"");
    return std::visit(
        Overloaded{[&](const BuiltinMethod&) -> std::string {
                       fail("\"" + cfg.label + "\" is a built-in preset: it has no uniforms");
                       return "";
                   },
                   [&](ShaderMethod& m) {
                       return setShaderUniform(m, param.substr(prefix.size()), value, file, field);
                   }},
        cfg.method);
}

}  // namespace pgt
