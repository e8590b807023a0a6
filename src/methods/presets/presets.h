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
// The surface a preset stands for at a scene's (s, b) (docs/methods.md "Engine presets"): the
// b its engine's convention expresses, as a multiple of s (a depth map -1, PlayCanvas's
// mid-grey -1/2, jME's -0.6, Babylon's offset and three.js 0; NaN: any b, the engine has a
// bias of its own), and for a GLSL preset the uniform that sets its amplitude, = factor x s
// (x l, world units per UV unit, where `perWorldUnit`), and the one that sets its bias as
// 1 + b / s (DarkPlaces' offset bias).
struct PresetSurface {
    double biasPerScale = NAN;
    std::string scaleUniform;
    double factor = 1;
    bool perWorldUnit = false;
    std::string biasUniform;
    std::string worldPerUvUniform;  // set to l (three.js's _tangents variants)
};

// A built-in preset is its configuration; a GLSL preset its shader file, the spec of it
// (everything but the source text, read by presetConfig) and what every method has.
struct MethodPreset {
    std::string name, source;
    MethodConfig
        config;     // a built-in's configuration at its shipped (s, b); a GLSL preset's common part
    GlslSpec glsl;  // GLSL presets: everything but the source text, shipped uniforms
    std::string shaderFile;  // GLSL presets: the file under shaderDir(); "" for built-ins
    PresetSurface surface;
    // NAME_tangents: the signs of V.x and V.y its function is fed, where the engine's path with
    // mesh tangents hands the function code written for its derivative frame's signs (Babylon:
    // -1, -1; PlayCanvas: 1, -1); 1, 1 elsewhere.
    double tangentsSignX = 1, tangentsSignY = 1;
};
const std::vector<MethodPreset>& methodPresets();

// The keys of a preset's sources in docs/references.md (space-separated): its engine's, or the
// document whose settings it is, by the name's first word ("godot_deep": "godot4").
std::string presetCite(const std::string& preset);
// A configuration's source keys: its preset's, else its built-in kind's; "" for a user's shader.
std::string sourceKeys(const MethodConfig& config);

// What a preset's amplitude is: the scene's surface (default: its engine's parameters mapped
// from the scene's, or the method's own, (s, b)), or the values its engine ships
// ("amplitude": "shipped").
enum class PresetAmplitude { Scene, Shipped };

// The configuration a preset stands for, labelled `label`; a GLSL preset's shader is read
// now (an error names `file` and `field`). `worldPerUv`: the base's l (three.js's scale is in
// world units).
MethodConfig presetConfig(const MethodPreset& preset, const std::string& label,
                          const std::string& file, const std::string& field,
                          PresetAmplitude amplitude = PresetAmplitude::Scene,
                          double worldPerUv = 1);

// Where the shipped GLSL files are: share/pgt/shaders (core/data_dir.h; PGT_SHADER_DIR in
// the environment wins).
std::string shaderDir();
// A scene's "glsl" value naming a shipped shader: "pgt:parallax.glsl" is
// shaderDir()/parallax.glsl, wherever pgt is installed.
inline constexpr const char* kShippedShaderPrefix = "pgt:";

}  // namespace pgt
