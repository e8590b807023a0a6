// A shader method's entry <-> its GlslSpec (methods/shader/glsl_spec.h), the shader half of
// methods/config.h: `{"name": ..., "glsl" | "hlsl": FILE, "function", "call", "defines",
// "sampler", "texture", "uniforms", "steps_uniform", "version", ...}` (docs/methods.md "GLSL
// methods"). setShaderParameter, glslTwin and twinEntry (methods/config.h) live here too.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "core/json_fields.h"
#include "methods/method.h"

namespace pgt {

// Parses a shader method's entry (its file is read now); the caller's `f` holds the entry.
MethodConfig parseShaderMethod(JsonFields& f, const std::string& file);
// The entry's shader part as JSON, into `j`: its file, entry, samplers, layout, call,
// defines, uniforms and the SHA-1 of its text.
void shaderJson(const GlslSpec& spec, nlohmann::json& j);

}  // namespace pgt
