// A shader method's entry <-> its GlslSpec: the shader half of methods/config.h (the entry
// through the fields' table, methods/shader/shader_fields.h; a varied uniform; the entry as
// JSON) and a built-in's GLSL twin.
#include "methods/shader/shader_config.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "core/format.h"
#include "core/json_read.h"
#include "methods/config.h"
#include "methods/presets/presets.h"
#include "methods/registry.h"
#include "methods/shader/glsl_spec.h"
#include "methods/shader/shader_fields.h"
#include "methods/shader/source_text.h"

namespace pgt {

std::vector<std::string> shaderEntryKeys() {
    std::vector<std::string> keys;
    for (const SpecField& row : specFields())
        keys.insert(keys.end(), row.keys.begin(), row.keys.end());
    return keys;
}

// {"name": "mine", "glsl" | "hlsl": FILE, ...}: the spec's fields (specFields), then the
// configuration's own (its name, lod, V, scale, bias, label); the file is read now.
MethodConfig parseShaderMethod(JsonFields& f, const std::string& file) {
    MethodConfig cfg;
    cfg.name = f.string("name", "");
    checkLabel(cfg.name, file, f.fieldPath("name"));  // a GLSL method's name is its label
    auto spec = std::make_shared<GlslSpec>();
    for (const SpecField& row : specFields()) row.read(f, *spec, file);
    cfg.discardOutside = f.boolean("discard_outside", false);
    // Level 0 or textureGrad with uv0's derivatives in the shaders that sample through
    // pgt_sample (docs/methods.md "GLSL methods").
    cfg.lodGrad = f.choice("lod", {"zero", "grad"}, "zero") == "grad";
    readMethodInputs(f, cfg);
    cfg.scale = f.number("scale", NAN, -kMaxOwnDisplacement, kMaxOwnDisplacement);
    cfg.bias = f.number("bias", NAN, -kMaxOwnDisplacement, kMaxOwnDisplacement);
    cfg.label = f.string("label", "");
    if (f.has("label")) checkLabel(cfg.label, file, f.fieldPath("label"));
    f.finish();
    cfg.method = ShaderMethod{std::move(spec)};
    return cfg;
}

std::string setShaderUniform(ShaderMethod& m, const std::string& name, const Json& value,
                             const std::string& file, const std::string& field) {
    auto fail = [&](const std::string& message) -> void {
        throw InputError(file, field, shortDump(value), message);
    };
    const GlslSpec::Uniform un = uniformValue(name, value, false, fail);
    auto spec = std::make_shared<GlslSpec>(*m.spec);  // configurations share no spec
    auto it = std::find_if(spec->uniforms.begin(), spec->uniforms.end(),
                           [&](const GlslSpec::Uniform& u) { return u.name == name; });
    if (it != spec->uniforms.end())
        *it = un;
    else if (mentionsIdentifier(spec->source, name))
        spec->uniforms.push_back(un);
    else
        fail("the shader " + spec->path + " has no uniform \"" + name + "\"");
    m.spec = std::move(spec);
    std::string part = name;
    for (size_t k = 0; k < un.values.size(); ++k) {
        if (k > 0) part += '_';
        part += formatNumber(un.values[k], 6);
    }
    return part;
}

// A shader's entry as JSON: every field's row (specFields), the text's SHA-1 among them.
void shaderJson(const GlslSpec& g, Json& j) {
    for (const SpecField& row : specFields()) row.write(g, j);
    j["precision"] = "float";
}

Json twinEntry(const MethodConfig& builtIn) {
    const BuiltinMethod* b = builtIn.builtin();
    if (!b || !kindInfo(b->kind).twin.file) return nullptr;
    const MethodKindInfo* info = &kindInfo(b->kind);
    const GlslTwin& twin = info->twin;
    Json j = {{"name", builtIn.label + "_gl"},
              {"glsl", std::string(kShippedShaderPrefix) + twin.file},
              {"function", twin.function}};
    for (const MapKindInfo& m : kMapKindTable)
        if (m.kind == MapKind::Height || twin.maps.has(m.kind))
            j[m.samplerKey] = twin.maps.has(m.kind) ? m.twinSampler : "";
    Json u = Json::object();
    if (twin.scaleBias) u["height_scale"] = "scale", u["height_bias"] = "bias";
    for (const IntParameter& p : info->parameters) {
        if (!p.written) continue;
        const bool asFloat = std::find(twin.floatParameters.begin(), twin.floatParameters.end(),
                                       p.key) != twin.floatParameters.end();
        u[p.key] = asFloat ? Json(double(p.get(*b))) : Json(p.get(*b));
    }
    if (!u.empty()) j["uniforms"] = u;
    if (builtIn.lodGrad) j["lod"] = "grad";
    return j;
}

MethodConfig glslTwin(const MethodConfig& builtIn) {
    const BuiltinMethod& b = *builtIn.builtin();
    const MethodKindInfo& info = kindInfo(b.kind);
    PGT_CHECK(info.twin.file != nullptr);
    const GlslTwin& twin = info.twin;
    auto spec = std::make_shared<GlslSpec>();
    spec->path = (std::filesystem::path(shaderDir()) / twin.file).lexically_normal().string();
    readShaderSource(*spec, spec->path, "glsl");
    spec->function = twin.function;
    spec->version = versionOfSource(*spec);
    for (const MapKindInfo& m : kMapKindTable)
        spec->samplers[size_t(m.kind)] = twin.maps.has(m.kind) ? m.twinSampler : "";
    if (twin.scaleBias)
        spec->uniforms = {{"height_bias", {}, false, "bias"}, {"height_scale", {}, false, "scale"}};
    for (const IntParameter& p : info.parameters) {
        if (!p.written) continue;
        const bool asFloat = std::find(twin.floatParameters.begin(), twin.floatParameters.end(),
                                       p.key) != twin.floatParameters.end();
        spec->uniforms.push_back({p.key, {double(p.get(b))}, !asFloat, "", 1});
    }
    MethodConfig cfg;
    cfg.name = cfg.label = builtIn.label + "_gl";
    cfg.lodGrad = builtIn.lodGrad;
    cfg.method = ShaderMethod{std::move(spec)};
    return cfg;
}

}  // namespace pgt
