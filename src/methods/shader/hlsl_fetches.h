// HLSL fetch counting (methods/shader/hlsl.cpp's preamble and texts; docs/methods.md
// "Fetches").
#pragma once

#include <string>
#include <vector>

namespace pgt::gl {

// `text` with each texture read counted as the GLSL wrapper counts reads: each read whose
// translation the wrapper's counters cover (texture, textureLod, textureGrad, texelFetch) is
// wrapped whole in pgt_counted(), which adds one to pgt_fetch_count and returns its argument
// (the coordinate alone would not do: glslang evaluates some, a Load's or a tex2Dlod's, once
// per part it splits off). Those reads: Sample, SampleBias, SampleLevel, SampleGrad,
// SampleCmp, SampleCmpLevelZero and a texture's Load, each without an offset argument; a
// texture's subscript T[p] and T.mips[l][p]; DX9's tex2D (two arguments or four), tex2Dbias,
// tex2Dlod and tex2Dgrad. The count survives the compiler dropping a fetch whose value is
// never used, as the GLSL counter keeps such a fetch alive: the same code counts the same in
// both languages. Every line keeps its number; calls in comments are left alone. `textures`:
// the names declared as textures in the file, its includes and pgt's preamble
// (textureNames), whose Load and subscripts are reads.
std::string countFetches(const std::string& text, const std::vector<std::string>& textures);
// The names `text` declares as a Texture1D-3D, TextureCube (array, multisampled) global or
// parameter.
std::vector<std::string> textureNames(const std::string& text);
// pgt_counted() for each coordinate type and pgt_fetch_count, for the preamble before the
// user's file.
std::string countingFunctions();

}  // namespace pgt::gl
