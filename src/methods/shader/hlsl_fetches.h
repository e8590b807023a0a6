// HLSL fetch counting (methods/shader/hlsl.cpp's preamble and texts; docs/methods.md
// "Fetches").
#pragma once

#include <string>

namespace pgt::gl {

// `text` with each texture read counted as the GLSL wrapper counts reads: each read whose
// translation the wrapper's counters cover (texture, textureLod, textureGrad, texelFetch:
// Sample, SampleBias, SampleLevel, SampleGrad, SampleCmp, SampleCmpLevelZero and Load without
// an offset argument; DX9's tex2D, tex2Dbias, tex2Dlod, tex2Dgrad) gets its coordinate (a DX9
// call: the whole call, since glslang evaluates a tex2Dlod or tex2Dbias coordinate once per
// component it splits off) wrapped in pgt_counted(), which adds one to pgt_fetch_count and
// returns its argument. The count survives the compiler dropping a fetch whose value is never
// used, as the GLSL counter keeps such a fetch alive: the same code counts the same in both
// languages. Every line keeps its number.
std::string countFetches(const std::string& text);
// pgt_counted() for each coordinate type and pgt_fetch_count, for the preamble before the
// user's file.
std::string countingFunctions();

}  // namespace pgt::gl
