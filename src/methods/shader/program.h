// Internal to gl/: the GLSL wrapper around a user's parallax function (a prelude that
// counts texture() calls, the user's file, a main() that runs the function once per output
// pixel), its compilation with driver messages mapped to the user's file and line, and the
// program cache.
#pragma once

#include "methods/shader/gl_api.h"

namespace pgt::gl {

// The linked program for the spec's file, function and samplers, compiled once per process.
// Compile and link errors throw InputError naming the user's file and line. Caller holds gMutex.
GLuint programFor(const GlslSpec& spec);

}  // namespace pgt::gl
