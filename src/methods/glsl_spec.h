// What a scene's GLSL method entry says (`{"name": ..., "glsl": FILE, ...}`, docs/methods.md "GLSL
// methods"): the shader's text, its entry function, samplers and uniforms. Data only: it is
// parsed in methods/config.cpp and run in OpenGL by gl/glsl_method.cpp.
#pragma once

#include <string>
#include <vector>

namespace pgt {

struct GlslSpec {
    std::string path;    // as resolved from the scene file's folder
    std::string source;  // the file's text (read when the scene is parsed)
    std::string function = "ParallaxMapping";
    std::string sampler = "depthMap";            // "" = the function samples no height map
    std::string normalSampler, parallaxSampler;  // optional: 003's derived maps
    std::string pyramidSampler;                  // optional: the minimum-maximum pyramid (maxmip)
    std::string coneSampler;         // optional: the conservative cone map for the sign of s (cone)
    std::string relaxedConeSampler;  // optional: the relaxed cone map (relaxed_cone)
    bool depthTexture = false;       // "texture": "depth" -> the sampler holds d = 1 - h
    // Uniforms set by name: 1 value -> float (int when written as an integer), 2-4 -> vecN;
    // or bound to the case's s ("scale") or b ("bias"), which a sweep varies.
    struct Uniform {
        std::string name;
        std::vector<double> values;
        bool isInt = false;
        std::string bind;  // "", "scale" or "bias"
    };
    std::vector<Uniform> uniforms;
};

}  // namespace pgt
