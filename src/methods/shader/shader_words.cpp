// A shader's text as words (methods/shader/shader_words.h).
#include "methods/shader/shader_words.h"

#include <algorithm>
#include <cctype>

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
        while (k > 0 && w[k - 1].ident &&
               (is(t, w[k - 1], "uniform") || is(t, w[k - 1], "lowp") ||
                is(t, w[k - 1], "mediump") || is(t, w[k - 1], "highp") ||
                is(t, w[k - 1], "static")))
            --k;
        if (k == 0 || boundary(t, w[k - 1])) return true;
    }
    return false;
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
