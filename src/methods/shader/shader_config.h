// A shader method's entry <-> its GlslSpec (methods/shader/glsl_spec.h), the shader half of
// methods/config.h: `{"name": ..., "glsl" | "hlsl": FILE, "function", "call", "defines",
// "sampler", "texture", "uniforms", "steps_uniform", "version", ...}` (docs/methods.md "GLSL
// methods"). setShaderParameter, glslTwin and twinEntry (methods/config.h) live here too.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/json_fields.h"
#include "methods/method.h"

namespace pgt {

// The keys of a shader entry's own fields, from the one table that reads them and writes
// their identity (docs/methods.md names each).
std::vector<std::string> shaderEntryKeys();
// Parses a shader method's entry (its file is read now); the caller's `f` holds the entry.
MethodConfig parseShaderMethod(JsonFields& f, const std::string& file);
// Sets the uniform `name` of a shader as a study varies it or a preset entry overrides it (a
// number or 2 to 4 numbers; one of the entry's uniforms or a name in the shader's source): the
// spec is copied first (configurations share none). Returns the label part ("max_layers16").
std::string setShaderUniform(ShaderMethod& m, const std::string& name, const nlohmann::json& value,
                             const std::string& file, const std::string& field);
// The entry's shader part as JSON, into `j`: its file, entry, samplers, layout, call,
// defines, uniforms and the SHA-1 of its text.
void shaderJson(const GlslSpec& spec, nlohmann::json& j);

}  // namespace pgt
