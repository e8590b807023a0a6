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

// Whether `text` holds `word` as a whole identifier.
inline bool mentionsIdentifier(const std::string& text, const std::string& word) {
    auto identChar = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
    for (size_t at = text.find(word); at != std::string::npos; at = text.find(word, at + 1))
        if ((at == 0 || !identChar(text[at - 1])) &&
            (at + word.size() == text.size() || !identChar(text[at + word.size()])))
            return true;
    return false;
}

struct GlslSpec {
    std::string path;    // as resolved from the scene file's folder (no file: the scene file)
    std::string source;  // the file's text (read when the scene is parsed); "" without one
    // Whether the entry names a file ("glsl" / "hlsl"); false: its "body" is all its code.
    bool ownFile = true;
    // Where each line of `source` came from, when GLSL #includes were expanded into it
    // (methods/shader/source_text.h); empty: every line is the file's own.
    struct LineOrigin {
        std::string file;
        int line = 0;
    };
    std::vector<LineOrigin> origins;
    // HLSL: every file its #include lines name (resolved path, text with line ends made LF),
    // read once when the scene is parsed: glslang is served these texts, never the disk again,
    // and the study's identity hashes them, so an edited include is another method. `included`:
    // their texts joined; `enums`: what they and the file declare.
    std::vector<std::pair<std::string, std::string>> includeFiles;
    // "include_paths": folders (resolved from the scene file's folder) searched, in order, for
    // an #include the including file's own folder does not hold.
    std::vector<std::string> includePaths;
    std::string included;
    std::vector<std::string> enums;
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
    // The channels of a "height" or "depth" texture that hold the value ("height.g",
    // "depth.a", "height.rgb": bits 1 R, 2 G, 4 B, 8 A), the others R, G, B 0 and A 1; 0: an
    // R32F texture (R the value, as GL reads G = B = 0 and A = 1 from it).
    unsigned channels = 0;
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
    // "body": statements in the source's language ending in `return <uv'>;`, with the names a
    // call has (for a function that answers through out/inout parameters, or code written as
    // statements in main()); empty: none. At most one of call and body is set.
    std::string body;
    // What runs, for messages: the function, the call or the body.
    std::string entryName() const {
        return !body.empty() ? "the body" : call.empty() ? function : "the call " + call;
    }
    // "sampler_state" (HLSL): the SamplerState that a function taking its texture and sampler
    // as parameters is called with; pgt declares it (and the texture) where the file does not.
    std::string samplerState;
    // "api": the framebuffer's y, as the engine's API has it: "gl" (OpenGL, WebGL: dFdy runs
    // up the image) or "d3d" (Direct3D, Vulkan, Metal, WebGPU: down). Default: GLSL gl, HLSL
    // d3d. Only derivatives (dFdy, ddy) see it.
    enum class Api { Gl, D3d };
    Api api = Api::Gl;
    bool defaultApi() const { return api == (hlsl ? Api::D3d : Api::Gl); }
    // "inputs": "engine": the function also gets what an engine's vertex stage would pass
    // (docs/methods.md "Engine inputs"): pgt_world_position, pgt_world_normal,
    // pgt_world_tangent (w: the handedness sign) and pgt_camera_position, with dFdx/dFdy on
    // them as a GPU has them, so that a frame built from derivatives or a V computed from the
    // camera runs as the engine runs it; "tangent" (default): uv and V only.
    bool engineInputs = false;
    // "vertex": the engine's own vertex shader (GLSL, Vulkan-style or GL), run on the base
    // mesh's vertices (methods/shader/vertex_stage.h; docs/methods.md "The engine's vertex
    // stage"). Its attributes are bound to pgt's vertex data and its matrix uniforms to pgt's
    // camera by name; each of the fragment code's stage inputs is the vertex output of its
    // location (or, without locations, its name), interpolated as a GPU's varyings are.
    struct VertexStage {
        std::string path, source;         // the file, read when the scene is parsed (includes in)
        std::vector<LineOrigin> origins;  // per line of `source` after an #include, else empty
        // Its attribute -> "position", "normal", "tangent" (w: the handedness sign),
        // "bitangent" or "uv".
        std::vector<std::pair<std::string, std::string>> attributes;
        // Its uniform -> "model", "view", "projection", "model_view", "view_projection",
        // "model_view_projection", "normal_matrix" or "camera_position".
        std::vector<std::pair<std::string, std::string>> matrices;
        // A vertex output and the fragment stage input it reaches: float or vecN (1 column of
        // `components` floats) or matN (N columns of N).
        struct Link {
            std::string output, input;
            int components = 0, columns = 1;
        };
        std::vector<Link> links;
        // "vectors": "row": the shader multiplies v * M (HLSL mul(v, M)), so each of
        // "matrices" is set transposed; "column" (false): M * v, mul(M, v).
        bool rowVectors = false;
        // HLSL (the entry's language): "vertex_entry", the vertex file's entry function;
        // "stage_input", the pixel stage's input as pgt's entry point declares it ("TYPE NAME",
        // default: the vertex entry's return type, named `input`); the file's includes and
        // enums as GlslSpec's; `glsl`, its translation (GLSL 4.50, made when the scene is
        // parsed: attributes pgt_in_SEMANTIC, outputs pgt_out_SEMANTIC).
        bool hlsl = false;
        std::string entry = "main", stageInput;
        std::vector<std::pair<std::string, std::string>> includeFiles;
        std::vector<std::string> enums;
        std::string glsl;
    };
    std::vector<VertexStage> vertex;  // at most one; empty: pgt's own inputs only
    const VertexStage* vertexStage() const { return vertex.empty() ? nullptr : &vertex[0]; }
    // "defines": #define NAME VALUE lines put before the source, in the entry's order.
    std::vector<std::pair<std::string, std::string>> defines;
    // Uniforms set by name: 1 value -> float (int when written as an integer), 2-4 -> vecN;
    // or bound to the case's s ("scale") or b ("bias"), which a sweep varies, times `factor`
    // (a preset's amplitude in its engine's units); "offset_bias": 1 + b / s (DarkPlaces'
    // offset bias, set by a preset on the scene's surface).
    struct Uniform {
        std::string name;
        std::vector<double> values;
        bool isInt = false;
        std::string bind;  // "", "scale", "bias" or "offset_bias"
        double factor = 1;
        // What the uniform is set to at the case's (or method's) s and b.
        std::vector<float> at(double s, double b) const {
            if (bind == "scale") return {float(factor * s)};
            if (bind == "bias") return {float(factor * b)};
            if (bind == "offset_bias") return {s != 0 ? float(1 + b / s) : 0.0f};
            return std::vector<float>(values.begin(), values.end());
        }
    };
    std::vector<Uniform> uniforms;
    // "steps_uniform": the integer uniform that is the method's step count, which `pgt fit`
    // sets to each of its step counts as it does a built-in's; "" where none.
    std::string stepsUniform;
    // Whether the case's (or the method's own) s ("scale") or b ("bias") reaches the shader,
    // through a uniform bound to it or a call or body that names it: what `pgt fit` varies.
    bool reaches(const std::string& param) const {
        for (const Uniform& u : uniforms)
            if (u.bind == param || u.bind == "offset_bias") return true;
        const std::string name = param == "scale" ? "s" : "b";
        return mentionsIdentifier(call, name) || mentionsIdentifier(body, name);
    }
};

}  // namespace pgt
