// The GLSL presets written again in C++ (src/methods/presets/*.glsl): each shader's function
// in float and the shader's order of operations, at the preset's shipped uniforms, reading the
// height map bilinearly as the GL does (a depth texture as 1 - h). They are every GLSL
// preset's second implementation, written from the same reading of the engine's code:
// tests/gl_engines_test.cpp runs each preset's shader against its twin on the same fragments,
// and a GLSL preset without a twin fails there. A preset's quirks are properties of its twin.
#pragma once

#include <functional>
#include <string>

#include "core/math.h"
#include "heightfield/texture.h"

namespace pgt {

struct PresetTwin {
    std::function<Vec2f(const Texture& height, Vec2f uv, Vec3f V)> run;
    // Head-on (V.xy = 0) the shader normalises vec2(0) and gives no finite uv' (jME's steep
    // parallax, Babylon's occlusion as shipped).
    bool nanHeadOn = false;
};

// The twin of the GLSL preset named `preset` at its shipped uniforms; null where there is none
// (a built-in preset, whose twin is its own C++ method).
const PresetTwin* presetTwin(const std::string& preset);

}  // namespace pgt
