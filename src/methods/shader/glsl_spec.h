// What a scene's GLSL method entry says (`{"name": ..., "glsl": FILE, ...}`, docs/methods.md "GLSL
// methods"): the shader's text, its entry function, samplers and uniforms. Data only: it is
// parsed in methods/config.cpp and run in OpenGL by methods/shader/glsl_method.cpp.
#pragma once

#include <array>
#include <cctype>
#include <string>
#include <utility>
#include <vector>

#include "methods/maps.h"

namespace pgt {

// A GLSL/HLSL identifier: a letter or '_', then letters, digits and '_' (function, sampler
// and macro names).
inline bool isShaderIdentifier(const std::string& s) {
    auto letter = [](char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; };
    if (s.empty() || !letter(s[0])) return false;
    for (char c : s)
        if (!(letter(c) || std::isdigit(static_cast<unsigned char>(c)))) return false;
    return true;
}

struct GlslSpec {
    std::string path;    // as resolved from the scene file's folder
    std::string source;  // the file's text (read when the scene is parsed)
    std::string function = "ParallaxMapping";
    // The dialect the file is written in (docs/methods.md "GLSL dialects"): "100" (ES 1.00,
    // WebGL 1), "300 es", "310 es", "320 es" or a desktop "110" ... "460", from the entry's
    // "version", else the file's #version line, else "110" (GLSL's own default). Every
    // dialect compiles in pgt's GLSL 4.50 core wrapper; the legacy ones (100, 110, 120) get
    // their texture2D family of names.
    std::string version = "110";
    bool isEs() const { return version == "100" || version.find(" es") != std::string::npos; }
    bool legacyTextureNames() const {
        return version == "100" || version == "110" || version == "120";
    }
    // The sampler uniform each map kind is bound to (methods/maps.h; the entry's
    // MapKindInfo::samplerKey), "" where the shader reads none: the height map's is
    // "depthMap" unless the entry says otherwise; the others are optional.
    std::array<std::string, kMapKinds> samplers = {"depthMap"};
    const std::string& sampler(MapKind k) const { return samplers[size_t(k)]; }
    // What the height sampler holds ("texture"; docs/methods.md "Texture layouts"): R = h
    // ("height"), R = 1 - h ("depth"), or RGBA with RGB = 0.5 + 0.5 m (the surface's unit
    // normal, Lengyel FGED 2's normal map at the case's s and b) and A = h ("normal+height") or 1 -
    // h
    // ("normal+depth"), as engines pack height into a normal map's alpha.
    enum class Layout { Height, Depth, NormalHeight, NormalDepth };
    Layout layout = Layout::Height;
    bool depthTexture() const { return layout == Layout::Depth || layout == Layout::NormalDepth; }
    bool packedNormal() const {
        return layout == Layout::NormalHeight || layout == Layout::NormalDepth;
    }
    // The source language: GLSL (any dialect above), or HLSL ("hlsl": FILE), which pgt
    // compiles to SPIR-V and back to GLSL 4.50 (methods/shader/hlsl.h) before the wrapper takes it.
    bool hlsl = false;
    // "call": an expression in the source's language giving uv' from uv, V, N = (0, 0, 1), s,
    // b and the uniforms; empty: the function F(uv, V) is called.
    std::string call;
    // What runs, for messages: the function, or the call.
    std::string entryName() const { return call.empty() ? function : "the call " + call; }
    // "defines": #define NAME VALUE lines put before the source, in the entry's order.
    std::vector<std::pair<std::string, std::string>> defines;
    // Uniforms set by name: 1 value -> float (int when written as an integer), 2-4 -> vecN;
    // or bound to the case's s ("scale") or b ("bias"), which a sweep varies.
    struct Uniform {
        std::string name;
        std::vector<double> values;
        bool isInt = false;
        std::string bind;  // "", "scale" or "bias"
    };
    std::vector<Uniform> uniforms;
    // "steps_uniform": the integer uniform that is the method's step count, which `pgt fit`
    // sets to each of its step counts as it does a built-in's; "" where none.
    std::string stepsUniform;
    // Whether the case's (or the method's own) s and b reach the shader, through a uniform
    // bound to "scale"/"bias" or a call (which may read s and b): what `pgt fit` varies.
    bool takesScale() const {
        if (!call.empty()) return true;
        for (const Uniform& u : uniforms)
            if (!u.bind.empty()) return true;
        return false;
    }
};

}  // namespace pgt
