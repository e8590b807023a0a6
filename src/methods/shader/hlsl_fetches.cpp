// HLSL fetch counting (methods/shader/hlsl_fetches.h).
#include "methods/shader/hlsl_fetches.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <utility>
#include <vector>

#include "methods/shader/conditional_lines.h"
#include "methods/shader/shader_words.h"

namespace pgt::gl {

namespace {

struct FetchCall {
    const char* name;
    bool method;   // `.Sample(`, or a function `tex2D(`
    size_t plain;  // the argument count without an offset
};
constexpr FetchCall kFetchCalls[] = {
    {"Sample", true, 2},     {"SampleBias", true, 3}, {"SampleLevel", true, 3},
    {"SampleGrad", true, 4}, {"SampleCmp", true, 3},  {"SampleCmpLevelZero", true, 3},
    {"Load", true, 1},       {"tex2D", false, 2},     {"tex2Dbias", false, 2},
    {"tex2Dlod", false, 2},  {"tex2Dgrad", false, 4}, {"tex2D", false, 4},
};

// The top-level arguments of the call whose '(' is at `open`: [begin, end) each; empty where
// the parentheses do not close.
std::vector<std::pair<size_t, size_t>> callArguments(const std::string& text, size_t open) {
    std::vector<std::pair<size_t, size_t>> args;
    int depth = 0;
    size_t begin = open + 1;
    for (size_t i = open; i < text.size(); ++i) {
        const char c = text[i];
        if (c == '(' || c == '[' || c == '{') {
            ++depth;
        } else if (c == ')' || c == ']' || c == '}') {
            if (--depth == 0) {
                args.emplace_back(begin, i);
                return args;
            }
        } else if (c == ',' && depth == 1) {
            args.emplace_back(begin, i);
            begin = i + 1;
        }
    }
    return {};
}

bool identChar(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

// Where the identifier that ends just before `end` begins (`end` where none does).
size_t identifierStart(const std::string& text, size_t end) {
    while (end > 0 && identChar(text[end - 1])) --end;
    return end;
}

// Where a method's receiver begins, its '.' at `dot`: `heightMap` of `heightMap.Load(`, or
// `maps[i]` of `maps[i].Load(`.
size_t receiverStart(const std::string& text, size_t dot) {
    size_t end = dot;
    if (end > 0 && text[end - 1] == ']') {
        int depth = 0;
        while (end > 0) {
            const char c = text[--end];
            if (c == ']') ++depth;
            if (c == '[' && --depth == 0) break;
        }
    }
    return identifierStart(text, end);
}

// Each read by a texture's subscript, `T[p]` and `T.mips[l][p]` (a texelFetch in the
// translation), in `plain` (comments blanked): [begin, end) of the whole expression (glslang
// evaluates a subscript's index more than once).
std::vector<std::pair<size_t, size_t>> subscriptReads(const std::string& plain,
                                                      const std::vector<std::string>& textures) {
    std::vector<std::pair<size_t, size_t>> out;
    for (const std::string& name : textures)
        for (size_t at = plain.find(name); at != std::string::npos;
             at = plain.find(name, at + name.size())) {
            size_t i = at + name.size();
            if ((at > 0 && (identChar(plain[at - 1]) || plain[at - 1] == '.')) ||
                (i < plain.size() && identChar(plain[i])))
                continue;
            while (i < plain.size() && plain[i] == ' ') ++i;
            if (plain.compare(i, 5, ".mips") == 0) {
                i += 5;
                while (i < plain.size() && plain[i] == ' ') ++i;
                if (i >= plain.size() || plain[i] != '[') continue;
                const auto level = callArguments(plain, i);
                if (level.size() != 1) continue;
                i = level[0].second + 1;
                while (i < plain.size() && plain[i] == ' ') ++i;
            }
            if (i >= plain.size() || plain[i] != '[') continue;
            const auto index = callArguments(plain, i);
            if (index.size() == 1) out.emplace_back(at, index[0].second + 1);
        }
    return out;
}

}  // namespace

std::vector<std::string> textureNames(const std::string& text) {
    // A texture type's word (RWTexture2DArray, TextureCube, ...), an optional template argument
    // list, then the name (shader_words.h: one pass, comments skipped).
    auto isTextureType = [](const std::string& w) {
        const std::string t = w.rfind("RW", 0) == 0 ? w.substr(2) : w;
        if (t.rfind("Texture", 0) != 0) return false;
        std::string rest = t.substr(7);
        for (const char* shape : {"1D", "2D", "3D", "Cube"})
            if (rest.rfind(shape, 0) == 0) {
                rest = rest.substr(std::strlen(shape));
                return rest.empty() || rest == "Array" || rest == "MS" || rest == "MSArray";
            }
        return false;
    };
    const std::vector<ShaderWord> w = shaderWords(text);
    std::vector<std::string> out;
    for (size_t k = 0; k < w.size(); ++k) {
        if (!w[k].ident || !isTextureType(wordText(text, w[k]))) continue;
        size_t n = k + 1;
        if (n < w.size() && wordText(text, w[n]) == "<") {  // Texture2D<float4>
            while (n < w.size() && wordText(text, w[n]) != ">") ++n;
            ++n;
        }
        if (n < w.size() && w[n].ident) out.push_back(wordText(text, w[n]));
    }
    return out;
}

std::string countFetches(const std::string& text, const std::vector<std::string>& textures) {
    // Found in the text with its comments blanked (the same length), so that a commented-out
    // call is not counted and cannot pull a parenthesis out of a comment.
    const std::string plain = blankComments(text);
    auto isTexture = [&](const std::string& name) {
        return std::find(textures.begin(), textures.end(), name) != textures.end();
    };
    std::vector<std::pair<size_t, const char*>> inserts;  // (position, text)
    auto wrap = [&](size_t begin, size_t end) {
        inserts.emplace_back(begin, "pgt_counted(");
        inserts.emplace_back(end, ")");
    };
    for (const FetchCall& call : kFetchCalls) {
        const std::string name = call.name;
        for (size_t at = plain.find(name); at != std::string::npos;
             at = plain.find(name, at + name.size())) {
            const size_t end = at + name.size();
            if (end < plain.size() && identChar(plain[end])) continue;
            if (call.method ? (at == 0 || plain[at - 1] != '.')
                            : (at > 0 && (identChar(plain[at - 1]) || plain[at - 1] == '.')))
                continue;
            // Load is also a buffer's: counted on a texture (or an element of an array of them).
            const bool load = name == "Load";
            if (load && at > 1 && plain[at - 2] != ']' &&
                !isTexture(plain.substr(identifierStart(plain, at - 1),
                                        at - 1 - identifierStart(plain, at - 1))))
                continue;
            size_t open = end;
            while (open < plain.size() && (plain[open] == ' ' || plain[open] == '\t')) ++open;
            if (open >= plain.size() || plain[open] != '(') continue;
            const auto args = callArguments(plain, open);
            if (args.size() != call.plain) continue;  // an offset form, or unbalanced
            // The whole call: glslang evaluates some coordinates once per part it splits off.
            wrap(call.method ? receiverStart(plain, at - 1) : at, args.back().second + 1);
        }
    }
    for (const auto& [begin, end] : subscriptReads(plain, textures)) wrap(begin, end);
    // From the end, so that the earlier positions hold.
    std::stable_sort(inserts.begin(), inserts.end(),
                     [](const auto& a, const auto& b) { return a.first > b.first; });
    std::string out = text;
    for (const auto& [pos, piece] : inserts) out.insert(pos, piece);
    return out;
}

std::string countingFunctions() {
    std::string out = "static float pgt_fetch_count = 0.0;\n";
    for (const char* t : {"float", "int", "uint"})
        for (const char* n : {"", "2", "3", "4"})
            out += std::string(t) + n + " pgt_counted(" + t + n +
                   " p) { pgt_fetch_count += 1.0; return p; }\n";
    return out;
}

}  // namespace pgt::gl
