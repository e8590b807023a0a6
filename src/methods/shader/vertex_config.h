// A shader entry's engine vertex stage (GlslSpec::VertexStage): `"vertex": FILE`,
// `"attributes": {NAME: "position" | "normal" | "tangent" | "uv"}` (default: by the
// attributes' names) and `"matrices": {UNIFORM: "model" | "view" | ...}` (docs/methods.md "The
// engine's vertex stage"). Part of methods/shader/shader_config.h's parsing.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "core/json_fields.h"
#include "methods/shader/glsl_spec.h"

namespace pgt {

// Reads the vertex file at `path` (the entry's "vertex", resolved) and its fields into
// `spec` (whose fragment code is read already), linking each of the fragment code's stage
// inputs to the vertex output of its location or name. Errors name the field.
void readVertexStage(JsonFields& f, GlslSpec& spec, const std::string& file,
                     const std::string& path);
// Its part of the entry's identity JSON: the file, its text's SHA-1 and the bindings.
void vertexStageJson(const GlslSpec::VertexStage& v, nlohmann::json& j);

}  // namespace pgt
