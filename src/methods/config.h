// Method configurations and JSON: the scene's "methods" list parsed into MethodConfig values
// (built-in kinds through the table of methods/registry.h, GLSL methods, presets), the
// labels that name their rows and files, and a configuration written back as JSON (for
// summary.json, results.csv's params and a study's identity).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/json_fields.h"
#include "methods/method.h"

namespace pgt {

// A method's own (s, b) in UV units: docs/model.md §3's displacement is at most a few UV units;
// 1e3 bounds a typo without limiting any real setting.
constexpr double kMaxOwnDisplacement = 1e3;

// Parses a "methods" array: each entry a name or an object {"name": ..., parameters}.
// Labels are unique: a method listed twice gets its parameters in the label ("pom_32").
// `worldPerUv`: the base's l, which a preset whose amplitude is in world units reads
// (methods/presets/presets.h).
std::vector<MethodConfig> parseMethods(const nlohmann::json& list, const std::string& file,
                                       const std::string& path, double worldPerUv = 1);
MethodConfig parseMethod(const nlohmann::json& entry, const std::string& file,
                         const std::string& path, double worldPerUv = 1);
// Reads the parameters of a built-in `cfg`'s kind that `f` holds (its integer parameters,
// scale, bias, discard_outside, precision) over cfg's current values. The caller calls f.finish(),
// which rejects every other key. A study varies a configuration through this.
void readMethodParameters(JsonFields& f, MethodConfig& cfg);
// What any method reads, as an engine hands it: "format": "float" | "unorm16" | "unorm8"
// (MethodConfig::format) and "V": "per_pixel" | "per_vertex" (MethodConfig::viewPerVertex).
void readMethodInputs(JsonFields& f, MethodConfig& cfg);
// Sets one parameter of a GLSL/HLSL method or a preset as a study varies it
// ("LABEL.PARAM": [values]) or a preset entry overrides it: "scale" or "bias" (the method's
// own s or b), or "uniforms.NAME" (a GLSL/HLSL method's or GLSL preset's uniform: a number or
// 2 to 4 numbers; NAME must be one of the entry's uniforms or appear in the shader's source).
// Returns the label part that names the value ("s0.05", "max_layers16"). `field` names the
// value in messages.
std::string setShaderParameter(MethodConfig& cfg, const std::string& param,
                               const nlohmann::json& value, const std::string& file,
                               const std::string& field);
// Gives every configuration without a label one (unique, with its parameters when its
// name is listed twice) and checks that the labels are unique; `path` names the list.
void assignLabels(std::vector<MethodConfig>& configs, const std::string& file,
                  const std::string& path);
nlohmann::json toJson(const MethodConfig& cfg);

// What differs between a built-in and a shader for parsing, JSON, studies and fits (the
// rest is evaluate/evaluate.h's: running, timing, compiling).
// The maps a configuration reads: a built-in's from its row of the method table
// (methods/registry.h), a shader's the kinds whose samplers its entry names.
MapSet needs(const MethodConfig& cfg);
// A fit's step count: a built-in's step parameter, a shader's "steps_uniform". setStepCount
// sets it (every field it sets); false where there is none.
bool hasStepCount(const MethodConfig& cfg);
bool setStepCount(MethodConfig& cfg, int steps);
// Whether `pgt fit` can vary its (s, b): not a preset (a fixed configuration), not a shader
// its (s, b) do not reach (no uniform bound to "scale"/"bias", no call).
enum class Fittable { Yes, Preset, ScaleUnused };
Fittable fittable(const MethodConfig& cfg);
// Whether the case's "scale" (s) or "bias" (b) reaches the method: always a built-in's; a
// shader's through a uniform bound to it or a call or body naming it. `pgt fit` varies and
// reports only what reaches.
bool reaches(const MethodConfig& cfg, const std::string& param);
// Whether its answer depends on (s, b) at all (every method but `none`).
bool readsDisplacement(const MethodConfig& cfg);
// Whether a study varies it through "LABEL.scale|bias|uniforms.NAME" (setShaderParameter: a
// shader or a preset) rather than through a built-in's own parameters (readMethodParameters).
bool variedAsShader(const MethodConfig& cfg);
// Whether it runs in OpenGL (a GLSL/HLSL method or GLSL preset) rather than in C++.
bool runsInGl(const MethodConfig& cfg);
// Whether its shader reads an engine's inputs ("inputs": "engine", GlslSpec::engineInputs).
bool readsEngineInputs(const MethodConfig& cfg);
// A built-in configuration's GLSL twin (its row of the method table, methods/registry.h:
// "LABEL_gl", the shipped shader, its samplers, s and b and the configuration's parameters as
// uniforms), made directly; the built-in's kind must have one. twinEntry writes the same as a
// scene's method entry (scenes/glsl_twins.json lists them); null when the kind has none.
MethodConfig glslTwin(const MethodConfig& builtIn);
nlohmann::json twinEntry(const MethodConfig& builtIn);

// A label a user writes (or a GLSL method's name): 1..kMaxLabelLength characters of
// A-Z a-z 0-9 _ - +, since it names CSV rows, EXR channels and files. Throws InputError.
constexpr size_t kMaxLabelLength = 64;
void checkLabel(const std::string& label, const std::string& file, const std::string& field);

}  // namespace pgt
