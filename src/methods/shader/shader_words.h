// A shader's text as words, for the few questions pgt asks of a user's file before a compiler
// sees it (which samplers it declares, which functions it defines, where its enums are). One
// pass, no regular expression: any file, however long its lines or runs of spaces, is read in
// time and stack proportional to its size (std::regex recurses per character and overflows
// the stack on runs of some 50,000).
#pragma once

#include <string>
#include <vector>

namespace pgt {

// An identifier or number (`ident` when it starts with a letter or '_'), or one punctuation
// character; comments, whitespace and string literals are skipped, and each preprocessor line
// (`#...` to its end, with its continuations) is one ";" word: a boundary between
// declarations, as a line of its own.
struct ShaderWord {
    size_t begin = 0, end = 0;  // [begin, end) in the text
    bool ident = false;
};
std::vector<ShaderWord> shaderWords(const std::string& text);

// A word's text.
inline std::string wordText(const std::string& text, const ShaderWord& w) {
    return text.substr(w.begin, w.end - w.begin);
}

// Whether `text` declares `name` at global scope with one of `types` (a template argument
// list after the type, `uniform` and precision qualifiers before it allowed): a declaration
// starts after ";", "}", a preprocessor line or the file's start and ends in ";", ":", "=",
// "[" or ",". A function parameter of that name is no declaration.
bool declaresGlobal(const std::string& text, const std::string& name,
                    const std::vector<std::string>& types);
// A Vulkan-style GLSL file as OpenGL 4.50 takes it, every line in its place: `set = N` and
// `push_constant` dropped from layout qualifiers; global stage inputs and outputs (`layout(
// location = 0) in vec2 inUV;`, `out vec4 outColor;`) made plain globals, which a "body" may
// assign (pgt's own stage feeds the entry); a uniform or push-constant block with an instance
// name made a struct and a uniform of it (its members set as "INSTANCE.MEMBER"), one without
// an instance name made its members uniforms; an `in` interface block likewise a struct and
// a global of it (or its members globals). `keepStageVariables` (a vertex stage pgt runs
// as a vertex shader): stage inputs and outputs stay, their locations too.
std::string vulkanGlslForGl(const std::string& text, bool keepStageVariables = false);
// A global stage variable: `layout(location = 1) in vec3 inNormal;` is {"inNormal", "vec3",
// 1}; location -1 where none is written.
struct StageVariable {
    std::string name, type;
    int location = -1;
    // A member of an interface block (`out VS_OUT { vec2 uv; } vs_out;`): the block's name and
    // the member's; `name` is then how the file reads it ("vs_out.uv", or "uv" without an
    // instance name).
    std::string block, member;
    bool array = false;         // `T name[N]` (type and name without the brackets)
    std::string interpolation;  // "flat" or "noperspective" where so qualified, else ""
};
// The file's global stage variables of `qualifier` ("in": also legacy `varying` and
// `attribute`; "out"), in order, an interface block's members each.
std::vector<StageVariable> stageVariables(const std::string& text, const std::string& qualifier);
// The types of each function named `name` that `text` defines or declares (`T name(`, T a
// word other than a statement's keyword).
std::vector<std::string> functionTypes(const std::string& text, const std::string& name);

}  // namespace pgt
