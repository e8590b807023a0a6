// Internal to gl/: the GLSL wrapper around a user's parallax function (a prelude that
// counts texture() calls, the user's file, a main() that runs the function once per output
// pixel), its compilation with driver messages mapped to the user's file and line, and the
// program cache.
#pragma once

#include <string>
#include <vector>

#include "methods/shader/gl_api.h"
#include "methods/shader/glsl_spec.h"

namespace pgt::gl {

// The linked program for the spec's file, function and samplers, compiled once per process.
// Compile and link errors throw InputError naming the user's file and line. Caller holds gMutex.
// Keyed by the program's text, so any setting that changes what is compiled is another program.
GLuint programFor(const GlslSpec& spec);

// Every uniform of `prog` back to its value as linked: called before each draw, so that a
// method sharing a program with another (the same text) never runs with the other's uniforms
// or sampler units. Caller holds gMutex, with `prog` in use.
void restoreLinkedValues(GLuint prog);

// The user's file as the wrapper holds it: its #version line and the #extension lines GL 4.50
// core has built in blanked, so every other line keeps its number.
std::string userLines(const std::string& src);
// A uniform by the name the user knows: GLSL's own; in HLSL (`hlsl`) a global or cbuffer
// member, which SPIRV-Cross makes a member of a plain uniform struct ("_12.NAME"), found among
// the active uniforms by its member name. -1 where none is active.
GLint uniformLocation(GLuint prog, bool hlsl, const std::string& name);
// A program of one vertex shader (`text`: `file`'s lines after its first `userFirst` lines,
// which are pgt's: "#version 450 core" and the entry's defines) whose outputs `captured`
// transform feedback records, interleaved. Compile and link errors throw InputError naming
// `file`'s lines (an #included line by its `origins`) and the field "vertex". Caller holds
// gMutex.
GLuint vertexProgram(const std::string& text, const std::string& file,
                     const std::vector<const char*>& captured, int userFirst,
                     const std::vector<GlslSpec::LineOrigin>& origins);

}  // namespace pgt::gl
