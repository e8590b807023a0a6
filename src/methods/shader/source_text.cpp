// A shader file's text as the compilers take it (methods/shader/source_text.h).
#include "methods/shader/source_text.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <set>
#include <sstream>

#include "core/error.h"
#include "core/interrupt.h"
#include "core/json_read.h"
#include "methods/shader/conditional_lines.h"
#include "methods/shader/shader_words.h"

namespace pgt {

std::string blankLineDirectives(const std::string& text, std::vector<std::string>& declared) {
    std::istringstream in(text);
    std::string out, line, source;
    long next = -1;  // the number the next line is declared to have (-1: no directive yet)
    declared.clear();
    while (std::getline(in, line)) {
        std::istringstream words(line);
        std::string directive, number, name;
        words >> directive >> number >> name;
        const bool isLine = directive == "#line" && !number.empty() &&
                            std::all_of(number.begin(), number.end(),
                                        [](char c) { return std::isdigit((unsigned char)c); });
        if (isLine) {
            declared.push_back("");
            next = std::stol(number.substr(0, 9));
            if (!name.empty()) source = name;
            out += "\n";
            continue;
        }
        declared.push_back(next < 0 ? ""
                                    : (source.empty() ? "" : source + ":") + std::to_string(next));
        if (next >= 0) ++next;
        out += line + "\n";
    }
    return out;
}

std::string normaliseLineEnds(std::string text) {
    if (text.rfind("\xEF\xBB\xBF", 0) == 0) text.erase(0, 3);
    if (text.find('\r') == std::string::npos) return text;
    std::string out;
    out.reserve(text.size());
    for (size_t i = 0; i < text.size(); ++i) {
        if (text[i] != '\r') {
            out += text[i];
        } else {
            out += '\n';
            if (i + 1 < text.size() && text[i + 1] == '\n') ++i;
        }
    }
    return out;
}

namespace {

// A shader's text holds no NUL byte (a binary file, or UTF-16): refused naming the file and the
// line, instead of the compiler seeing the text end there ("lacks main").
std::string withoutNul(std::string text, const std::string& path, const std::string& field,
                       const std::string& what) {
    const size_t at = text.find('\0');
    if (at != std::string::npos)
        throw InputError(
            path, field, "",
            what + " holds a NUL byte on line " +
                std::to_string(1 + std::count(text.begin(), text.begin() + long(at), '\n')) +
                " (a binary file, or text in UTF-16?)");
    return text;
}

int countNewlines(const std::string& s) { return int(std::count(s.begin(), s.end(), '\n')); }

// The braces as words (named, so that no brace stands unmatched in the code's text).
constexpr const char* kOpen = "\x7b";
constexpr const char* kClose = "\x7d";

bool isWord(const std::string& t, const ShaderWord& w, const char* s) {
    return t.compare(w.begin, w.end - w.begin, s) == 0 &&
           std::char_traits<char>::length(s) == w.end - w.begin;
}

// One change to a text: [begin, end) becomes `with`.
struct Edit {
    size_t begin, end;
    std::string with;
};
std::string applyEdits(const std::string& t, std::vector<Edit> edits) {
    std::sort(edits.begin(), edits.end(),
              [](const Edit& a, const Edit& b) { return a.begin < b.begin; });
    std::string out;
    size_t at = 0;
    for (const Edit& e : edits) {
        if (e.begin < at) continue;  // overlapping: the first wins
        out.append(t, at, e.begin - at);
        out += e.with;
        at = e.end;
    }
    out.append(t, at, std::string::npos);
    return out;
}

// `#include "F"` or `#include <F>` on a line: F, else "".
std::string includeTarget(const std::string& line) {
    size_t i = line.find_first_not_of(" \t");
    if (i == std::string::npos || line[i] != '#') return "";
    i = line.find_first_not_of(" \t", i + 1);
    if (i == std::string::npos || line.compare(i, 7, "include") != 0) return "";
    i = line.find_first_not_of(" \t", i + 7);
    if (i == std::string::npos || (line[i] != '"' && line[i] != '<')) return "";
    const size_t close = line.find(line[i] == '"' ? '"' : '>', i + 1);
    return close == std::string::npos ? "" : line.substr(i + 1, close - i - 1);
}

// The enums of a text: each `enum [class|struct] E [: T] { members };` as its span (from
// `enum` to the ';'), its name, whether scoped, and its members' words.
struct EnumDecl {
    size_t begin = 0, end = 0;
    std::string name;
    bool scoped = false;
    size_t first = 0, last = 0;  // the members' words [first, last)
};
std::vector<EnumDecl> enumDeclarations(const std::string& t, const std::vector<ShaderWord>& w) {
    std::vector<EnumDecl> out;
    for (size_t i = 0; i + 3 < w.size(); ++i) {
        if (!isWord(t, w[i], "enum")) continue;
        EnumDecl e;
        size_t j = i + 1;
        e.scoped = isWord(t, w[j], "class") || isWord(t, w[j], "struct");
        if (e.scoped) ++j;
        if (j >= w.size() || !w[j].ident) continue;
        e.name = wordText(t, w[j++]);
        if (j + 1 < w.size() && isWord(t, w[j], ":")) j += 2;  // the underlying type
        if (j >= w.size() || !isWord(t, w[j], kOpen)) continue;
        size_t k = j + 1;
        while (k < w.size() && !isWord(t, w[k], kClose) && !isWord(t, w[k], kOpen)) ++k;
        if (k + 1 >= w.size() || !isWord(t, w[k], kClose) || !isWord(t, w[k + 1], ";")) continue;
        e.begin = w[i].begin;
        e.end = w[k + 1].end;
        e.first = j + 1;
        e.last = k;
        out.push_back(e);
        i = k + 1;
    }
    return out;
}

// The constants of an enum: a member without a value one more than the one before (the
// first 0).
std::string enumConstants(const std::string& t, const std::vector<ShaderWord>& w,
                          const EnumDecl& e) {
    std::ostringstream out;
    out << "typedef int " << e.name << ";";
    std::string previous;
    for (size_t i = e.first; i < e.last;) {
        size_t end = i;
        while (end < e.last && !isWord(t, w[end], ",")) ++end;
        if (end > i && w[i].ident) {
            const std::string member = wordText(t, w[i]);
            const std::string qualified = e.name + "_" + member;
            std::string value;
            if (i + 1 < end && isWord(t, w[i + 1], "="))
                value = t.substr(w[i + 2 < end ? i + 2 : i + 1].begin,
                                 w[end - 1].end - w[i + 2 < end ? i + 2 : i + 1].begin);
            std::replace(value.begin(), value.end(), '\n', ' ');
            out << " static const int " << qualified << " = ";
            if (!value.empty())
                out << "(" << value << ");";
            else if (previous.empty())
                out << "0;";
            else
                out << "(" << previous << " + 1);";
            if (!e.scoped) out << " static const int " << member << " = " << qualified << ";";
            previous = qualified;
        }
        i = end + 1;
    }
    return out.str();
}

// The files `text` includes (resolved path, text), to `depth` levels, each once.
void collectIncludes(const std::string& path, const std::string& text, size_t depth,
                     std::set<std::string>& seen, size_t& bytes, ConditionalLines& cond,
                     std::vector<std::pair<std::string, std::string>>& out,
                     const std::vector<std::string>& searchPaths, Branch from = Branch::Active) {
    if (depth >= kMaxIncludeDepth) return;
    std::istringstream in(blankComments(text));
    cond.enterFile(from);
    for (std::string line; std::getline(in, line);) {
        const std::string target = includeTarget(line);
        const Branch branch = cond.next(line);
        if (branch == Branch::Skipped || target.empty()) continue;
        throwIfCancelled();
        const std::string name = resolveInclude(path, target, searchPaths);
        if (!seen.insert(name).second) continue;
        std::string sub;
        try {
            sub = normaliseLineEnds(
                readTextFile(name, path, "#include", "HLSL include", kMaxShaderBytes));
        } catch (const std::exception&) {
            continue;  // glslang names a file it cannot include when it compiles
        }
        withoutNul(sub, name, "#include", "the HLSL include");
        bytes += sub.size() + 1;
        out.emplace_back(name, sub);
        if (bytes > kMaxShaderBytes) break;
        collectIncludes(name, sub, depth + 1, seen, bytes, cond, out, searchPaths, branch);
    }
    cond.leaveFile();
}

}  // namespace

std::vector<std::pair<std::string, std::string>> hlslIncludes(
    const std::string& path, const std::string& text,
    const std::vector<std::pair<std::string, std::string>>& defines,
    const std::vector<std::string>& searchPaths) {
    std::set<std::string> seen = {std::filesystem::path(path).lexically_normal().string()};
    size_t bytes = 0;
    std::vector<std::pair<std::string, std::string>> out;
    ConditionalLines cond(defines);
    collectIncludes(path, text, 0, seen, bytes, cond, out, searchPaths);
    return out;
}

std::string resolveInclude(const std::string& including, const std::string& target,
                           const std::vector<std::string>& searchPaths) {
    namespace fs = std::filesystem;
    const std::string beside =
        (fs::path(including).parent_path() / target).lexically_normal().string();
    std::error_code ec;
    if (fs::is_regular_file(beside, ec) || fs::path(target).is_absolute()) return beside;
    for (const std::string& dir : searchPaths) {
        const std::string there = (fs::path(dir) / target).lexically_normal().string();
        if (fs::is_regular_file(there, ec)) return there;
    }
    return beside;
}

std::vector<std::string> hlslEnumNames(const std::string& text) {
    std::vector<std::string> names;
    for (const EnumDecl& e : enumDeclarations(text, shaderWords(text))) names.push_back(e.name);
    return names;
}

std::string hlslEnumsAsConstants(const std::string& text, const std::vector<std::string>& known) {
    const std::vector<ShaderWord> w = shaderWords(text);
    std::vector<Edit> edits;
    std::set<std::string> names(known.begin(), known.end());
    for (const EnumDecl& e : enumDeclarations(text, w)) {
        names.insert(e.name);
        // The constants on the enum's first line, then its line breaks: no later line moves.
        edits.push_back(
            {e.begin, e.end,
             enumConstants(text, w, e) +
                 std::string(size_t(countNewlines(text.substr(e.begin, e.end - e.begin))), '\n')});
    }
    for (size_t i = 0; i + 3 < w.size(); ++i)  // E::A -> E_A
        if (w[i].ident && isWord(text, w[i + 1], ":") && isWord(text, w[i + 2], ":") &&
            w[i + 3].ident && names.count(wordText(text, w[i])))
            edits.push_back(
                {w[i].begin, w[i + 3].end, wordText(text, w[i]) + "_" + wordText(text, w[i + 3])});
    return edits.empty() ? text : applyEdits(text, std::move(edits));
}

namespace {

// The word after the one that closes the bracket opened at `open` (`o`, `c`: the pair).
size_t matching(const std::string& t, const std::vector<ShaderWord>& w, size_t open, const char* o,
                const char* c) {
    size_t k = open + 1;
    for (int depth = 1; k < w.size(); ++k) {
        depth += isWord(t, w[k], o) - isWord(t, w[k], c);
        if (depth == 0) break;
    }
    return k;
}

// A function's parameters, [first, last) words each, split at the top-level commas of the
// words between `open` and `close` (its parentheses).
using WordRange = std::pair<size_t, size_t>;
std::vector<WordRange> parametersOf(const std::string& t, const std::vector<ShaderWord>& w,
                                    size_t open, size_t close) {
    std::vector<WordRange> params;
    size_t from = open + 1;
    for (size_t k = open + 1, depth = 0; k <= close; ++k) {
        if (k == close || (depth == 0 && isWord(t, w[k], ","))) {
            if (k > from) params.push_back({from, k});
            from = k + 1;
        } else {
            depth += isWord(t, w[k], "(") - isWord(t, w[k], ")");
        }
    }
    return params;
}

std::string rangeText(const std::string& t, const std::vector<ShaderWord>& w, WordRange r) {
    return t.substr(w[r.first].begin, w[r.second - 1].end - w[r.first].begin);
}

// The '=' word of a parameter with a default (a value after it), else 0.
size_t defaultOf(const std::string& t, const std::vector<ShaderWord>& w, WordRange p) {
    for (size_t k = p.first; k + 1 < p.second; ++k)
        if (isWord(t, w[k], "=")) return k;
    return 0;
}

bool samplerParameter(const std::string& t, const std::vector<ShaderWord>& w, WordRange p) {
    size_t type = p.first;
    while (type < p.second && (isWord(t, w[type], "in") || isWord(t, w[type], "uniform"))) ++type;
    return type < p.second &&
           (isWord(t, w[type], "SamplerState") || isWord(t, w[type], "SamplerComparisonState") ||
            isWord(t, w[type], "sampler"));
}

// A function TYPE NAME(params) whose parameters from `first` on have defaults: an overload
// for each number of them left out, which passes them.
std::string defaultOverloads(const std::string& t, const std::vector<ShaderWord>& w,
                             const std::string& type, const std::string& name,
                             const std::vector<WordRange>& params, size_t first) {
    std::string out;
    for (size_t kept = first; kept < params.size(); ++kept) {
        std::string list, args;
        for (size_t k = 0; k < params.size(); ++k) {
            const std::string sep = k ? ", " : "";
            if (k >= kept) {
                const size_t eq = defaultOf(t, w, params[k]);
                args += sep + rangeText(t, w, {eq + 1, params[k].second});
                continue;
            }
            list += sep + rangeText(t, w, params[k]);
            size_t nameWord = params[k].second - 1;  // the last identifier before a ':'
            for (size_t q = params[k].first; q < params[k].second; ++q)
                if (isWord(t, w[q], ":")) nameWord = q - 1;
            args += sep + wordText(t, w[nameWord]);
        }
        out += " " + type + " " + name + "(" + list + ") " + kOpen + " " +
               (type == "void" ? "" : "return ") + name + "(" + args + "); " + kClose;
    }
    return out;
}

}  // namespace

std::string hlslSamplerDefaults(const std::string& text) {
    static const char* kNotTypes[] = {"return", "if", "while", "for", "switch", "else"};
    const std::vector<ShaderWord> w = shaderWords(text);
    std::vector<Edit> edits;
    for (size_t i = 0; i + 2 < w.size(); ++i) {
        // TYPE NAME ( parameters ) { body }
        if (!w[i].ident || !w[i + 1].ident || !isWord(text, w[i + 2], "(") ||
            std::any_of(std::begin(kNotTypes), std::end(kNotTypes),
                        [&](const char* k) { return isWord(text, w[i], k); }))
            continue;
        const size_t close = matching(text, w, i + 2, "(", ")");
        if (close + 1 >= w.size() || !isWord(text, w[close + 1], kOpen)) continue;
        const size_t end = matching(text, w, close + 1, kOpen, kClose);
        if (end >= w.size()) continue;
        const std::vector<WordRange> params = parametersOf(text, w, i + 2, close);
        size_t first = params.size();  // the first parameter with a default
        bool sampler = false;
        for (size_t k = params.size(); k-- > 0 && defaultOf(text, w, params[k]) > 0;) {
            first = k;
            sampler = sampler || samplerParameter(text, w, params[k]);
        }
        if (!sampler || first == params.size()) continue;
        // The definition without its defaults (each `= value` blanked, line breaks kept), and
        // after its body, on the same line, the overloads that pass them.
        for (size_t k = first; k < params.size(); ++k) {
            const size_t b = w[defaultOf(text, w, params[k])].begin,
                         e = w[params[k].second - 1].end;
            std::string blank = text.substr(b, e - b);
            for (char& c : blank)
                if (c != '\n') c = ' ';
            edits.push_back({b, e, blank});
        }
        edits.push_back({w[end].end, w[end].end,
                         defaultOverloads(text, w, wordText(text, w[i]), wordText(text, w[i + 1]),
                                          params, first)});
        i = end;
    }
    return edits.empty() ? text : applyEdits(text, std::move(edits));
}

bool takePragmaOnce(std::string& text) {
    bool found = false;
    // Under "#if 0" (a branch certainly skipped) a #pragma once is none. The comment-blanked
    // copy's lines are the text's, walked in step (a blanked pragma only shortens its line).
    std::istringstream lines(blankComments(text));
    ConditionalLines cond({}, false);
    for (size_t at = 0; at < text.size();) {
        size_t end = text.find('\n', at);
        if (end == std::string::npos) end = text.size();
        std::string line;
        std::getline(lines, line);
        size_t i = text.find_first_not_of(" \t", at);
        // Skipped, or a pragma inside a comment (the blanked line has none): not one.
        if (cond.next(line) == Branch::Skipped || line.find("pragma") == std::string::npos) i = end;
        if (i < end && text[i] == '#') {
            i = text.find_first_not_of(" \t", i + 1);
            if (i < end && text.compare(i, 6, "pragma") == 0) {
                i = text.find_first_not_of(" \t", i + 6);
                const size_t tail = i < end ? text.find_first_not_of(" \t", i + 4) : end;
                if (i < end && text.compare(i, 4, "once") == 0 && (tail >= end)) {
                    text.erase(at, end - at);  // the line blanked, its break kept
                    found = true;
                    end = at;
                }
            }
        }
        at = end + 1;
    }
    return found;
}

namespace {

// GLSL's #include, expanded in place, each line's origin recorded.
class GlslIncludes {
  public:
    std::string text;
    std::vector<GlslSpec::LineOrigin> origins;
    bool any = false;

    GlslIncludes(const std::vector<std::pair<std::string, std::string>>& defines,
                 const std::vector<std::string>& searchPaths)
        : cond_(defines), searchPaths_(searchPaths) {}

    // Each line kept (an include in a branch certainly skipped, or in one pgt cannot judge
    // whose file is missing, blanked: the compiler skips or names it); the includes expanded.
    void expand(const std::string& path, std::string source, size_t depth,
                Branch from = Branch::Active) {
        if (takePragmaOnce(source)) once_.insert(path);
        std::istringstream in(source), plain(blankComments(source));
        std::string line, bare;
        cond_.enterFile(from);
        for (int n = 1; std::getline(in, line); ++n) {
            std::getline(plain, bare);
            const Branch branch = cond_.next(bare);
            const std::string target = includeTarget(bare);
            if (target.empty()) {
                text += line + "\n";
                origins.push_back({path, n});
                continue;
            }
            any = true;
            throwIfCancelled();  // an include fan-out: Ctrl-C in Python stops between files
            const std::string name = resolveInclude(path, target, searchPaths_);
            std::error_code ec;
            if (branch == Branch::Skipped) {
                text += "\n";
                origins.push_back({path, n});
                continue;
            }
            if (branch == Branch::Unknown && !std::filesystem::is_regular_file(name, ec)) {
                // Left to the compiler's preprocessor: skipped there, or named if taken.
                text += "#error pgt cannot read the include " + target + "\n";
                origins.push_back({path, n});
                continue;
            }
            if (depth + 1 > kMaxIncludeDepth)
                throw InputError(path, "#include", target,
                                 "includes nest more than " + std::to_string(kMaxIncludeDepth) +
                                     " deep (a file that includes itself?)");
            if (once_.count(name)) {  // its #pragma once: included already
                text += "\n";
                origins.push_back({path, n});
                continue;
            }
            std::string sub = withoutNul(
                normaliseLineEnds(readTextFile(name, path + ":" + std::to_string(n), "#include",
                                               "GLSL include", kMaxShaderBytes)),
                name, "#include", "the GLSL include");
            bytes_ += sub.size();
            if (bytes_ > kMaxShaderBytes)
                throw InputError(path, "#include", target,
                                 "the file and its includes pass " +
                                     std::to_string(kMaxShaderBytes >> 20) + " MiB");
            expand(name, std::move(sub), depth + 1, branch);
        }
        cond_.leaveFile();
    }

  private:
    ConditionalLines cond_;
    const std::vector<std::string>& searchPaths_;
    std::set<std::string> once_;
    size_t bytes_ = 0;
};

}  // namespace

void readShaderSource(GlslSpec& spec, const std::string& owner, const std::string& field) {
    std::string text = withoutNul(
        normaliseLineEnds(readTextFile(spec.path, owner, field, "shader file", kMaxShaderBytes)),
        spec.path, field, "the shader file");
    spec.origins.clear();
    if (spec.hlsl) {  // glslang includes the HLSL files (methods/shader/hlsl.cpp)
        takePragmaOnce(text);
        spec.includeFiles = hlslIncludes(spec.path, text, spec.defines, spec.includePaths);
        spec.included.clear();
        for (const auto& [name, sub] : spec.includeFiles) spec.included += sub + "\n";
        spec.enums = hlslEnumNames(text + spec.included);
        spec.source = hlslSamplerDefaults(hlslEnumsAsConstants(text, spec.enums));
        return;
    }
    spec.source = expandGlslIncludes(spec.path, std::move(text), spec.defines, spec.includePaths,
                                     spec.origins);
}

std::string expandGlslIncludes(const std::string& path, std::string text,
                               const std::vector<std::pair<std::string, std::string>>& defines,
                               const std::vector<std::string>& searchPaths,
                               std::vector<GlslSpec::LineOrigin>& origins) {
    origins.clear();
    GlslIncludes includes(defines, searchPaths);
    includes.expand(path, text, 0);
    if (!includes.any) return text;  // the file's own text, byte for byte (its SHA-1 names it)
    origins = std::move(includes.origins);
    return std::move(includes.text);
}

}  // namespace pgt
