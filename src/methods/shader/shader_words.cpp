// A shader's text as words (methods/shader/shader_words.h).
#include "methods/shader/shader_words.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>

namespace pgt {

namespace {

bool wordChar(char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.';
}

// The end of the line at `i` (its '\n' or the text's end), backslash continuations included.
size_t lineEnd(const std::string& t, size_t i) {
    while (i < t.size() && t[i] != '\n') i += t[i] == '\\' && i + 1 < t.size() ? 2 : 1;
    return i;
}

}  // namespace

std::vector<ShaderWord> shaderWords(const std::string& t) {
    std::vector<ShaderWord> out;
    bool lineStart = true;  // only whitespace since the last line break
    size_t i = 0;
    while (i < t.size()) {
        const char c = t[i];
        if (c == '\n') {
            lineStart = true;
            ++i;
        } else if (std::isspace(static_cast<unsigned char>(c))) {
            ++i;
        } else if (c == '/' && i + 1 < t.size() && t[i + 1] == '/') {
            i = lineEnd(t, i);
        } else if (c == '/' && i + 1 < t.size() && t[i + 1] == '*') {
            const size_t close = t.find("*/", i + 2);
            i = close == std::string::npos ? t.size() : close + 2;
        } else if (c == '#' && lineStart) {
            const size_t end = lineEnd(t, i);
            out.push_back({i, i + 1, false});  // a boundary, as ';'
            i = end;
        } else if (c == '"') {
            size_t j = i + 1;
            while (j < t.size() && t[j] != '"' && t[j] != '\n') j += t[j] == '\\' ? 2 : 1;
            i = std::min(j + 1, t.size());
            lineStart = false;
        } else if (wordChar(c)) {
            size_t j = i;
            while (j < t.size() && wordChar(t[j])) ++j;
            out.push_back({i, j, std::isalpha(static_cast<unsigned char>(c)) || c == '_'});
            i = j;
            lineStart = false;
        } else {
            out.push_back({i, i + 1, false});
            ++i;
            lineStart = false;
        }
    }
    return out;
}

namespace {

bool is(const std::string& t, const ShaderWord& w, const char* s) {
    return t.compare(w.begin, w.end - w.begin, s) == 0 &&
           std::char_traits<char>::length(s) == w.end - w.begin;
}

// A preprocessor line's word ('#' stands for the whole line) or ';' or '}'.
bool boundary(const std::string& t, const ShaderWord& w) {
    return !w.ident && (t[w.begin] == ';' || t[w.begin] == '}' || t[w.begin] == '#');
}

}  // namespace

bool declaresGlobal(const std::string& t, const std::string& name,
                    const std::vector<std::string>& types) {
    const std::vector<ShaderWord> w = shaderWords(t);
    for (size_t i = 0; i < w.size(); ++i) {
        if (!w[i].ident || !is(t, w[i], name.c_str())) continue;
        if (i + 1 >= w.size() || w[i + 1].ident ||
            std::string(";:=[,").find(t[w[i + 1].begin]) == std::string::npos)
            continue;
        size_t j = i;
        if (j > 0 && is(t, w[j - 1], ">")) {  // Texture2D<float4> NAME
            while (j > 0 && !is(t, w[j - 1], "<")) --j;
            if (j > 0) --j;
        }
        if (j == 0 || !w[j - 1].ident) continue;
        const std::string type = wordText(t, w[j - 1]);
        if (std::find(types.begin(), types.end(), type) == types.end()) continue;
        size_t k = j - 1;
        for (bool more = true; more && k > 0;) {
            more = false;
            if (w[k - 1].ident && (is(t, w[k - 1], "uniform") || is(t, w[k - 1], "lowp") ||
                                   is(t, w[k - 1], "mediump") || is(t, w[k - 1], "highp") ||
                                   is(t, w[k - 1], "static"))) {
                --k, more = true;
            } else if (is(t, w[k - 1], ")")) {  // layout(binding = 0, set = 1) (Vulkan GLSL)
                size_t open = k - 1;
                while (open > 0 && !is(t, w[open], "(")) --open;
                if (open > 0 && is(t, w[open - 1], "layout")) k = open - 1, more = true;
            }
        }
        if (k == 0 || boundary(t, w[k - 1])) return true;
    }
    return false;
}

namespace {

// Edits of a text by position, applied from the last: each replaces [begin, end).
struct TextEdit {
    size_t begin, end;
    std::string with;
};

std::string applyEdits(std::string text, std::vector<TextEdit> edits) {
    std::sort(edits.begin(), edits.end(),
              [](const TextEdit& a, const TextEdit& b) { return a.begin > b.begin; });
    for (const TextEdit& e : edits) text.replace(e.begin, e.end - e.begin, e.with);
    return text;
}

// Blanks [begin, end) but its line breaks (so no line moves).
TextEdit blank(const std::string& t, size_t begin, size_t end) {
    std::string with = t.substr(begin, end - begin);
    for (char& c : with)
        if (c != '\n') c = ' ';
    return {begin, end, with};
}

// The word after the one that closes the bracket opened at word `open` ('(' or '{').
size_t closing(const std::string& t, const std::vector<ShaderWord>& w, size_t open) {
    const char o = t[w[open].begin], c = o == '(' ? ')' : '}';
    int depth = 0;
    for (size_t k = open; k < w.size(); ++k) {
        if (!w[k].ident && t[w[k].begin] == o) ++depth;
        if (!w[k].ident && t[w[k].begin] == c && --depth == 0) return k;
    }
    return w.size() - 1;
}

bool oneOf(const std::string& t, const ShaderWord& w, std::initializer_list<const char*> names) {
    for (const char* n : names)
        if (is(t, w, n)) return true;
    return false;
}

// A layout group `layout ( ... )` at words [at, close]: edits dropping `set = N` and
// `push_constant` (the whole group when nothing else is left, or when `all`).
void editLayout(const std::string& t, const std::vector<ShaderWord>& w, size_t at, size_t close,
                bool all, std::vector<TextEdit>& edits) {
    std::vector<std::pair<size_t, size_t>> items;  // words of each comma-separated item
    size_t start = at + 2;
    for (size_t k = start; k <= close; ++k)
        if (k == close || is(t, w[k], ",")) items.push_back({start, k}), start = k + 1;
    size_t kept = 0;
    std::vector<TextEdit> mine;
    for (size_t i = 0; i < items.size(); ++i) {
        const auto [a, b] = items[i];
        const bool drop = a < b && (is(t, w[a], "set") || is(t, w[a], "push_constant"));
        if (!drop) {
            ++kept;
            continue;
        }
        // The item and the comma before it (or after it, for the first).
        const size_t from = i > 0 ? w[a - 1].begin : w[a].begin;
        const size_t to = i > 0 || b >= close ? w[b - 1].end : w[b].end;
        mine.push_back(blank(t, from, to));
    }
    if (all || kept == 0)
        edits.push_back(blank(t, w[at].begin, w[close].end));
    else
        edits.insert(edits.end(), mine.begin(), mine.end());
}

// `uniform NAME { members } [inst];` from its `uniform` word: with an instance name, `struct
// NAME { members }; uniform NAME inst;`; without, its members as uniforms. Returns the word
// after the block's '}'.
size_t editUniformBlock(const std::string& t, const std::vector<ShaderWord>& w, size_t uniform,
                        std::vector<TextEdit>& edits) {
    const size_t open = uniform + 2, close = closing(t, w, open);
    if (close + 1 < w.size() && w[close + 1].ident) {
        edits.push_back({w[uniform].begin, w[uniform].end, "struct"});
        edits.push_back({w[close].end, w[close].end, "; uniform " + wordText(t, w[uniform + 1])});
        return close + 1;
    }
    edits.push_back(blank(t, w[uniform].begin, w[open].end));
    for (size_t m = open + 1; m < close; ++m) {
        edits.push_back({w[m].begin, w[m].begin, "uniform "});
        while (m < close && !is(t, w[m], ";")) ++m;
    }
    edits.push_back(blank(t, w[close].begin, w[close].end));
    return close + 1;
}

// The members `type name;` of the block whose '{' is word `open` (arrays left out).
std::vector<std::pair<std::string, std::string>> blockMembers(const std::string& t,
                                                              const std::vector<ShaderWord>& w,
                                                              size_t open) {
    std::vector<std::pair<std::string, std::string>> out;
    const size_t close = closing(t, w, open);
    size_t start = open + 1;
    for (size_t k = start; k < close; ++k) {
        if (!is(t, w[k], ";")) continue;
        if (k >= start + 2 && w[k - 1].ident && w[k - 2].ident)
            out.emplace_back(wordText(t, w[k - 2]), wordText(t, w[k - 1]));
        start = k + 1;
    }
    return out;
}

// `in NAME { members } [inst];` from its `in` word (an interface block between stages): with an
// instance name, `struct NAME { members }; NAME inst;`; without, its members plain globals.
void editStageBlock(const std::string& t, const std::vector<ShaderWord>& w, size_t stage,
                    size_t open, std::vector<TextEdit>& edits) {
    const size_t close = closing(t, w, open);
    if (close + 1 < w.size() && w[close + 1].ident) {
        edits.push_back({w[stage].begin, w[stage].end, "struct"});
        edits.push_back({w[close].end, w[close].end, "; " + wordText(t, w[stage + 1])});
        return;
    }
    edits.push_back(blank(t, w[stage].begin, w[open].end));
    edits.push_back(blank(t, w[close].begin, w[close].end));
}

// An opening brace as a word's text (named: a literal brace in code confuses simple tools
// that count a function's braces).
constexpr const char* kOpenBrace = "{";

// A global declaration: words [k, end) up to its ';' or '{' (end), its layout groups, and the
// first `in`/`out`/`varying` and `uniform` word among them (w.size(): none).
struct GlobalDeclaration {
    size_t k = 0, end = 0, stage = 0, uniform = 0;
    std::vector<size_t> layouts;  // each layout group's first word
    bool block = false;           // ends in '{'
};

// Every global declaration of `t`, in order; a function's body (or any other block) skipped.
std::vector<GlobalDeclaration> globalDeclarations(const std::string& t,
                                                  const std::vector<ShaderWord>& w) {
    std::vector<GlobalDeclaration> out;
    size_t k = 0;
    while (k < w.size()) {
        GlobalDeclaration d;
        d.k = k, d.end = k, d.stage = w.size(), d.uniform = w.size();
        while (d.end < w.size() && !is(t, w[d.end], ";") && !is(t, w[d.end], kOpenBrace) &&
               !boundary(t, w[d.end]))
            d.end = is(t, w[d.end], "(") ? closing(t, w, d.end) + 1 : d.end + 1;
        for (size_t j = k; j < d.end; ++j) {
            if (is(t, w[j], "layout") && j + 1 < d.end && is(t, w[j + 1], "("))
                d.layouts.push_back(j);
            if (oneOf(t, w[j], {"in", "out", "varying", "attribute"}) && d.stage == w.size())
                d.stage = j;
            if (is(t, w[j], "uniform") && d.uniform == w.size()) d.uniform = j;
            if (is(t, w[j], "(")) j = closing(t, w, j);
        }
        d.block = d.end < w.size() && is(t, w[d.end], kOpenBrace);
        k = d.block ? closing(t, w, d.end) + 1 : d.end + 1;
        out.push_back(std::move(d));
    }
    return out;
}

}  // namespace

std::string vulkanGlslForGl(const std::string& t, bool keepStageVariables) {
    const std::vector<ShaderWord> w = shaderWords(t);
    std::vector<TextEdit> edits;
    for (const GlobalDeclaration& d : globalDeclarations(t, w)) {
        const bool inOut = d.stage < d.end && oneOf(t, w[d.stage], {"in", "out"});
        if (d.block && d.uniform < d.end && d.end == d.uniform + 2) {  // uniform NAME {...} [inst];
            for (size_t l : d.layouts) editLayout(t, w, l, closing(t, w, l + 1), true, edits);
            editUniformBlock(t, w, d.uniform, edits);
        } else if (d.block && inOut && d.uniform == w.size() && !keepStageVariables &&
                   d.end == d.stage + 2) {  // an interface block: a struct and its instance
            for (size_t l : d.layouts) editLayout(t, w, l, closing(t, w, l + 1), true, edits);
            editStageBlock(t, w, d.stage, d.end, edits);
        } else if (!d.block && inOut && d.uniform == w.size() && !keepStageVariables) {
            // A stage variable: a plain global.
            for (size_t l : d.layouts) editLayout(t, w, l, closing(t, w, l + 1), true, edits);
            for (size_t j = d.k; j < d.end; ++j)
                if (oneOf(t, w[j], {"in", "out", "flat", "smooth", "noperspective", "centroid"}))
                    edits.push_back(blank(t, w[j].begin, w[j].end));
        } else {
            for (size_t l : d.layouts) editLayout(t, w, l, closing(t, w, l + 1), false, edits);
        }
    }
    return applyEdits(t, std::move(edits));
}

std::vector<StageVariable> stageVariables(const std::string& t, const std::string& qualifier) {
    const std::vector<ShaderWord> w = shaderWords(t);
    std::vector<StageVariable> out;
    for (const GlobalDeclaration& d : globalDeclarations(t, w)) {
        if (d.stage >= d.end || d.uniform < d.end) continue;
        const std::string q = wordText(t, w[d.stage]);
        if (d.block && q == qualifier && d.end == d.stage + 2) {  // an interface block's members
            const std::string block = wordText(t, w[d.stage + 1]);
            const size_t close = closing(t, w, d.end);
            const std::string inst =
                close + 1 < w.size() && w[close + 1].ident ? wordText(t, w[close + 1]) : "";
            for (const auto& [type, member] : blockMembers(t, w, d.end))
                out.push_back({inst.empty() ? member : inst + "." + member, type, -1, block, member,
                               false, ""});
            continue;
        }
        if (d.block) continue;
        const bool wanted = q == qualifier || (qualifier == "in" && q == "varying") ||
                            (qualifier == "in" && q == "attribute");
        if (!wanted || d.end < d.stage + 3) continue;
        StageVariable v;
        v.type = wordText(t, w[d.end - 2]);
        v.name = wordText(t, w[d.end - 1]);
        if (!w[d.end - 1].ident || !w[d.end - 2].ident) {  // an array: `T name[N]`
            size_t open = d.end;
            while (open > d.stage && !is(t, w[open - 1], "[")) --open;
            if (open < d.stage + 3 || !w[open - 2].ident || !w[open - 3].ident) continue;
            v.type = wordText(t, w[open - 3]);
            v.name = wordText(t, w[open - 2]);
            v.array = true;
        }
        for (size_t j = d.k; j < d.stage; ++j)
            if (is(t, w[j], "flat") || is(t, w[j], "noperspective"))
                v.interpolation = wordText(t, w[j]);
        for (size_t l : d.layouts) {
            const size_t close = closing(t, w, l + 1);
            for (size_t j = l + 2; j + 2 < close; ++j)
                if (is(t, w[j], "location") && is(t, w[j + 1], "="))
                    v.location = std::atoi(wordText(t, w[j + 2]).c_str());
        }
        out.push_back(std::move(v));
    }
    return out;
}

std::vector<std::string> functionTypes(const std::string& t, const std::string& name) {
    static const char* kStatements[] = {"return", "else", "case", "do", "new", "delete"};
    const std::vector<ShaderWord> w = shaderWords(t);
    std::vector<std::string> out;
    for (size_t i = 1; i + 1 < w.size(); ++i) {
        if (!w[i].ident || !is(t, w[i], name.c_str()) || !is(t, w[i + 1], "(") || !w[i - 1].ident)
            continue;
        const std::string type = wordText(t, w[i - 1]);
        if (std::none_of(std::begin(kStatements), std::end(kStatements),
                         [&](const char* s) { return type == s; }))
            out.push_back(type);
    }
    return out;
}

}  // namespace pgt
