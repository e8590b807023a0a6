// HLSL methods (docs/methods.md "HLSL"): the user's HLSL, with an entry point pgt adds,
// compiled to SPIR-V by glslang's HLSL front end (with SPIRV-Tools' legalisation) and turned
// back into GLSL 4.50 by SPIRV-Cross, in the form the GLSL wrapper (methods/shader/program.cpp)
// takes: a function pgt_hlsl_call(uv, V) returning uv'. Separate Texture2D and SamplerState objects
// become one sampler2D named after the texture; globals and cbuffer members become members
// of plain uniform structs (set by member name, methods/shader/glsl_method.cpp).
#pragma once

#include <string>
#include <vector>

#include "methods/shader/glsl_spec.h"

namespace pgt::gl {

// The function the translated text defines (the wrapper's PGT_FUNCTION).
inline constexpr const char* kHlslCall = "pgt_hlsl_call";

// The GLSL 4.50 text of the spec's HLSL method. A compile error throws InputError naming the
// user's file and line (or "call" for the call expression). Runs without a GL context.
std::string hlslToGlsl(const GlslSpec& spec);

// A semantic as D3D matches it: upper case, with its index (POSITION is POSITION0).
std::string semanticKey(std::string s);
// What a translation names the stage variable of semantic `semantic` (semanticKey's form) that
// is not one of pgt's own: pgt_in_SEMANTIC or pgt_out_SEMANTIC.
inline std::string hlslStageName(bool input, const std::string& semantic) {
    return (input ? "pgt_in_" : "pgt_out_") + semantic;
}
// A stage variable of an HLSL stage: its semantic as D3D matches it (upper case, with its
// index: POSITION0), its floats per column (1-4; 0 for any other type) and columns (a matrix's
// as its translation holds it, else 1).
struct HlslVarying {
    std::string semantic;
    int components = 0, columns = 1;
    std::string interpolation;  // "nointerpolation" or "noperspective" where so qualified
};
// The spec's HLSL vertex stage (GlslSpec::VertexStage, `hlsl`) as GLSL 4.50: its entry
// function's inputs named pgt_in_SEMANTIC, its outputs pgt_out_SEMANTIC (SV_Position is
// gl_Position). A compile error throws InputError naming the vertex file, field "vertex".
struct HlslVertexStage {
    std::string glsl;
    std::vector<HlslVarying> inputs, outputs;
};
HlslVertexStage hlslVertexToGlsl(const GlslSpec& spec);
// The pixel stage's inputs beyond pgt's own that its translation reads (the stage input
// struct's members the call uses), named pgt_in_SEMANTIC in it.
std::vector<HlslVarying> hlslPixelInputs(const GlslSpec& spec);

}  // namespace pgt::gl
