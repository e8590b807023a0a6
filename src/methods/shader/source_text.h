// A shader file's text as pgt's compilers take it, whatever the engine wrote it with: a UTF-8
// byte-order mark dropped and CRLF (or CR) line ends made LF; GLSL's `#include` expanded in
// place (GLSL has none; engines split their parallax over files); HLSL's `enum` made constants
// (glslang reserves the word); `#pragma once` kept in both. Every line keeps its number, or,
// after a GLSL include, its origin (GlslSpec::origins), so that messages name the right file
// and line (docs/methods.md "Your engine's file").
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "methods/shader/glsl_spec.h"

namespace pgt {

// Includes nest at most this deep: a file that includes itself (directly or round a cycle) is
// refused at that depth, naming the file, instead of expanding forever.
inline constexpr size_t kMaxIncludeDepth = 32;
// A shader is a few KB; 16 MiB bounds a stray file (and a file with its includes).
inline constexpr size_t kMaxShaderBytes = 16u << 20;

// Drops a leading UTF-8 byte-order mark and makes CRLF and lone CR line ends LF.
std::string normaliseLineEnds(std::string text);

// A file's own `#line N ["S"]` directives blanked (so a compiler's line numbers are the
// lines' places in the text, which pgt maps to files), and per line of `text` what such a
// directive declared for it ("S:N" or "N"; "" before any): the messages show both.
std::string blankLineDirectives(const std::string& text, std::vector<std::string>& declared);

// HLSL: each `enum [class] E [: T] { A [= x], B, ... };` becomes `typedef int E;` and
// `static const int` constants, E_A for each member (and A too for a plain enum), with `E::A`
// written E_A for E declared here or in `known`; on the enum's own lines, so that no later
// line moves.
std::string hlslEnumsAsConstants(const std::string& text, const std::vector<std::string>& known);
// The files an HLSL file's #include lines name, resolved relative to the including file's
// folder (as glslang asks for them), each once, to kMaxIncludeDepth levels: (path, text with
// line ends made LF). One that cannot be read is left out, for the compile to name; one under
// a conditional certainly skipped with `defines` (conditional_lines.h) is not read.
std::vector<std::pair<std::string, std::string>> hlslIncludes(
    const std::string& path, const std::string& text,
    const std::vector<std::pair<std::string, std::string>>& defines,
    const std::vector<std::string>& searchPaths = {});
// The file an `#include "target"` of the file `including` reads: beside it, else in the first
// of `searchPaths` that holds it (GlslSpec::includePaths), else beside it (for the error).
std::string resolveInclude(const std::string& including, const std::string& target,
                           const std::vector<std::string>& searchPaths);
// The enums `text` declares (for `E::A` across files).
std::vector<std::string> hlslEnumNames(const std::string& text);

// HLSL: a function whose trailing parameters default to a sampler (`SamplerState s =
// sampler_linear_wrap`, which glslang refuses) loses those defaults and gains, after its body
// on the same line, an overload without them that passes them.
std::string hlslSamplerDefaults(const std::string& text);

// `#pragma once` lines blanked; true when the text had one.
bool takePragmaOnce(std::string& text);

// Reads spec.path into spec.source (and spec.origins) as above; `owner` and `field` name
// where the path came from in messages.
void readShaderSource(GlslSpec& spec, const std::string& owner, const std::string& field);
// A GLSL file's `#include` lines expanded in place (conditionals judged with `defines`,
// targets found as resolveInclude finds them), each line's origin in `origins` (left empty,
// and the text returned as it is, where the file includes nothing).
std::string expandGlslIncludes(const std::string& path, std::string text,
                               const std::vector<std::pair<std::string, std::string>>& defines,
                               const std::vector<std::string>& searchPaths,
                               std::vector<GlslSpec::LineOrigin>& origins);

}  // namespace pgt
