// Named configurations: engine defaults and the source documents' own settings, used as
// {"preset": NAME} in a method list (docs/methods.md "Engine presets" gives each one's source).
// Built-in presets are MethodConfig values; GLSL presets are our re-implementations of the
// engines' shader code paths, in src/methods/presets/, read when a scene names them.
#pragma once

#include <string>
#include <vector>

#include "methods/method.h"
#include "methods/shader/glsl_spec.h"

namespace pgt {

// A built-in preset is its configuration; a GLSL preset its shader file, the spec of it
// (everything but the source text, read by presetConfig) and what every method has.
struct MethodPreset {
    std::string name, source;
    MethodConfig config;     // a built-in's configuration; a GLSL preset's common part
    GlslSpec glsl;           // GLSL presets: everything but the source text
    std::string shaderFile;  // GLSL presets: the file under shaderDir(); "" for built-ins
};
const std::vector<MethodPreset>& methodPresets();

// The configuration a preset stands for, labelled `label`; a GLSL preset's shader is read
// now (an error names `file` and `field`).
MethodConfig presetConfig(const MethodPreset& preset, const std::string& label,
                          const std::string& file, const std::string& field);

// Where the shipped GLSL files are: share/pgt/shaders (core/data_dir.h; PGT_SHADER_DIR in
// the environment wins).
std::string shaderDir();
// A scene's "glsl" value naming a shipped shader: "pgt:parallax.glsl" is
// shaderDir()/parallax.glsl, wherever pgt is installed.
inline constexpr const char* kShippedShaderPrefix = "pgt:";

}  // namespace pgt
