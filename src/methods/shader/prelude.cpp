// The GLSL wrapper's prelude (methods/shader/prelude.h).
#include "methods/shader/prelude.h"

namespace pgt::gl {

namespace {

// The wrapper: a prelude that counts texture() calls, the user's file (its #version line
// blanked, so its lines keep their numbers), and a main() that feeds the function one
// fragment per output pixel.
constexpr const char* kPrelude = R"(#version 450 core
int pgt_fetches = 0;
uniform int pgt_lod_grad;  // the method's "lod": 1 = "grad", 0 = "zero"
vec2 pgt_uv_dx = vec2(0.0), pgt_uv_dy = vec2(0.0);  // uv0's derivatives (the rasteriser's)
// How pgt's built-in shaders sample a map: level 0, or textureGrad with uv0's derivatives.
vec4 pgt_sample(sampler2D s, vec2 p) {
    pgt_fetches++;
    return pgt_lod_grad != 0 ? textureGrad(s, p, pgt_uv_dx, pgt_uv_dy) : textureLod(s, p, 0.0);
}
vec4 pgt_texture(sampler2D s, vec2 p) { pgt_fetches++; return texture(s, p); }
vec4 pgt_texture(sampler2D s, vec2 p, float b) { pgt_fetches++; return texture(s, p, b); }
vec4 pgt_textureLod(sampler2D s, vec2 p, float l) { pgt_fetches++; return textureLod(s, p, l); }
vec4 pgt_textureGrad(sampler2D s, vec2 p, vec2 dx, vec2 dy) {
    pgt_fetches++; return textureGrad(s, p, dx, dy); }
vec4 pgt_texelFetch(sampler2D s, ivec2 p, int l) { pgt_fetches++; return texelFetch(s, p, l); }
)";
constexpr const char* kTextureNames = R"(#define texture pgt_texture
#define textureLod pgt_textureLod
#define textureGrad pgt_textureGrad
#define texelFetch pgt_texelFetch
)";

// The counting functions for every other sampler type a file may declare (a Vulkan shader's
// array of layers, a cube map, a shadow map, integer textures), so that a `texture()` on them
// compiles under kTextureNames' names, and counts: the sampler, texture()'s coordinate, the
// derivatives' type, texelFetch's coordinate ("" where GLSL has none) and what it returns.
struct SamplerOverload {
    const char *type, *coord, *grad, *fetch, *value;
    bool bias = true, lod = true;
};
constexpr SamplerOverload kSamplerOverloads[] = {
    {"sampler1D", "float", "float", "int", "vec4"},
    {"sampler1DArray", "vec2", "float", "ivec2", "vec4"},
    {"sampler2DArray", "vec3", "vec2", "ivec3", "vec4"},
    {"sampler3D", "vec3", "vec3", "ivec3", "vec4"},
    {"samplerCube", "vec3", "vec3", "", "vec4"},
    {"samplerCubeArray", "vec4", "vec3", "", "vec4"},
    {"isampler2D", "vec2", "vec2", "ivec2", "ivec4"},
    {"usampler2D", "vec2", "vec2", "ivec2", "uvec4"},
    {"sampler2DShadow", "vec3", "vec2", "", "float"},
    {"samplerCubeShadow", "vec4", "vec3", "", "float", true, false},
    {"sampler2DArrayShadow", "vec4", "vec2", "", "float", false, false},
};

std::string samplerOverloads() {
    std::string out;
    for (const SamplerOverload& o : kSamplerOverloads) {
        const std::string t = o.type, c = o.coord, g = o.grad, v = o.value;
        const std::string head = v + " pgt_";
        out +=
            head + "texture(" + t + " s, " + c + " p) { pgt_fetches++; return texture(s, p); }\n";
        if (o.bias)
            out += head + "texture(" + t + " s, " + c +
                   " p, float b) { pgt_fetches++; return texture(s, p, b); }\n";
        if (o.lod)
            out += head + "textureLod(" + t + " s, " + c +
                   " p, float l) { pgt_fetches++; return textureLod(s, p, l); }\n";
        out += head + "textureGrad(" + t + " s, " + c + " p, " + g + " dx, " + g +
               " dy) { pgt_fetches++; return textureGrad(s, p, dx, dy); }\n";
        if (*o.fetch)
            out += head + "texelFetch(" + t + " s, " + o.fetch +
                   " p, int l) { pgt_fetches++; return texelFetch(s, p, l); }\n";
    }
    return out;
}

}  // namespace

const std::string& preludeText() {
    static const std::string text = std::string(kPrelude) + samplerOverloads() + kTextureNames;
    return text;
}

}  // namespace pgt::gl
