// What a shader compiler is given, bounded first (docs/testing.md "What pgt promises"): the GL
// driver's compiler (Mesa's, NVIDIA's) runs inside pgt's process, and hostile GLSL -- a sum of
// 20,000 terms, a chain of thousands of calls, a macro bomb -- overflows its stack, or runs
// for minutes and takes gigabytes. So the exact fragment source is first parsed by glslang in
// a child process (core/process.h) held to a time and a memory limit, its syntax tree
// measured, and a shader past a bound is refused with the bound it passed. HLSL's compile runs
// in such a child too (methods/shader/hlsl.cpp).
#pragma once

#include <string>

#include "core/process.h"

namespace pgt::gl {

// The bounds (measured on Mesa 22.3's llvmpipe: a 20,000-term sum overflowed its stack where
// 10,000 compiled; a chain of 1,000 calls each adding to the last took 8 s and 965 MB,
// 3,000 took 59 s and 6.9 GB).
struct ShaderBounds {
    int expressionDepth = 2000;  // nesting of one expression or statement tree
    int callDepth = 64;          // the longest chain of calls between functions
    int functions = 4096;        // functions defined
    long nodes = 1000000;        // syntax tree nodes in all
};
ShaderBounds shaderBounds();

// The limits of a compiler's child: 30 s, and what the memory limit (--memory-limit) leaves
// beside pgt's own resident memory (at least 64 MB).
ChildLimits compileLimits();
// Why a compiler's child ended without an answer, for a message: "crashed (signal 11)", "ran
// longer than ...", "needed more than ...".
std::string compileFailure(const ChildStatus& st, const ChildLimits& limits);
// Writes all of `data` to fd; false on a write error.
bool writeAll(int fd, const std::string& data);

// Parses `fragmentSource` (GLSL 4.50, the text the GL will compile) with glslang in a child
// and refuses it (InputError on `file`, field `field`) when a bound is passed, glslang crashes
// on it, or it runs past the child's limits. A parse error is not a refusal: the GL's own
// compiler reports the shader's errors.
void checkShaderBounds(const std::string& fragmentSource, const std::string& file,
                       const std::string& field);

}  // namespace pgt::gl
