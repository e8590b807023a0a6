// Internal to methods/shader/: a shader entry's own fields as one table (read into the spec,
// written into its identity) and the helpers methods/shader/shader_config.cpp shares with it.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/json_fields.h"
#include "methods/shader/glsl_spec.h"

namespace pgt {

// A shader entry's own fields, one row each (docs/methods.md "GLSL methods"): the keys it
// reads, how it reads them into the spec and how it writes them into the entry's identity
// (shaderJson, what a study hashes). Rows run in the table's order, which the reading needs:
// the file after its "defines" and "include_paths" (its #ifdef lines and includes), its
// dialect and steps uniform after its text. The program's key is its text
// (methods/shader/program.cpp), so a field that changes what is compiled needs no row
// elsewhere.
struct SpecField {
    std::vector<std::string> keys;
    void (*read)(JsonFields& f, GlslSpec& s, const std::string& file);
    void (*write)(const GlslSpec& g, nlohmann::json& j);
};
const std::vector<SpecField>& specFields();

// One uniform's value as an entry writes it: a number (int when written as an integer), 2 to
// 4 numbers, or, where `binds`, "scale" / "bias" (the case's s / b). `fail(message)` throws.
GlslSpec::Uniform uniformValue(const std::string& name, const nlohmann::json& value, bool binds,
                               const std::function<void(const std::string&)>& fail);
// The dialect of the spec's source: its #version line (a desktop number or "N es"), else "110".
std::string versionOfSource(const GlslSpec& spec);

}  // namespace pgt
