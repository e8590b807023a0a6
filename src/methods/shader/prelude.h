// Internal to gl/: the prelude of pgt's GLSL wrapper (methods/shader/program.h): its #version,
// pgt_sample and the fetch-counting functions of every sampler type, under the names a user's
// file calls (texture, textureLod, textureGrad, texelFetch).
#pragma once

#include <string>

namespace pgt::gl {

// The prelude's text, made once.
const std::string& preludeText();

}  // namespace pgt::gl
