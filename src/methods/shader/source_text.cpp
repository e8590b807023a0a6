// A shader file's text as the compilers take it (methods/shader/source_text.h).
#include "methods/shader/source_text.h"

#include <algorithm>
#include <filesystem>
#include <regex>
#include <set>
#include <sstream>

#include "core/error.h"
#include "core/json_read.h"

namespace pgt {

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

int countNewlines(const std::string& s) { return int(std::count(s.begin(), s.end(), '\n')); }

// The members of an enum's body "A = 1, B, C = B + 2": `static const int` lines, a member
// without a value one more than the one before (the first 0).
std::string enumConstants(const std::string& name, const std::string& body, bool scoped) {
    static const std::regex member(R"(^\s*([A-Za-z_]\w*)\s*(?:=\s*([\s\S]*?))?\s*$)");
    std::ostringstream out;
    out << "typedef int " << name << ";";
    std::string previous;
    std::stringstream items(body);
    std::string item;
    while (std::getline(items, item, ',')) {
        std::smatch m;
        if (!std::regex_match(item, m, member)) continue;  // a trailing comma's empty item
        const std::string qualified = name + "_" + m[1].str();
        std::string value = m[2].str();
        std::replace(value.begin(), value.end(), '\n', ' ');
        out << " static const int " << qualified << " = ";
        if (!value.empty())
            out << "(" << value << ");";
        else if (previous.empty())
            out << "0;";
        else
            out << "(" << previous << " + 1);";
        if (!scoped) out << " static const int " << m[1].str() << " = " << qualified << ";";
        previous = qualified;
    }
    return out.str();
}

}  // namespace

namespace {

const std::regex& enumDeclaration() {
    static const std::regex declaration(
        R"(\benum\s+(class\s+|struct\s+)?([A-Za-z_]\w*)\s*(?::\s*[A-Za-z_]\w*\s*)?\{([^{}]*)\}\s*;)");
    return declaration;
}

// The text of the files `text` includes, to `depth` levels, each once.
void collectIncludes(const std::string& path, const std::string& text, size_t depth,
                     std::set<std::string>& seen, std::string& out) {
    static const std::regex include(R"((?:^|\n)[ \t]*#[ \t]*include[ \t]*["<]([^">\n]+)[">])");
    if (depth >= kMaxIncludeDepth) return;
    for (auto it = std::sregex_iterator(text.begin(), text.end(), include);
         it != std::sregex_iterator(); ++it) {
        const std::string name = (std::filesystem::path(path).parent_path() / (*it)[1].str())
                                     .lexically_normal()
                                     .string();
        if (!seen.insert(name).second) continue;
        try {
            const std::string sub = normaliseLineEnds(
                readTextFile(name, path, "#include", "HLSL include", kMaxShaderBytes));
            out += sub + "\n";
            if (out.size() > kMaxShaderBytes) return;
            collectIncludes(name, sub, depth + 1, seen, out);
        } catch (const std::exception&) {
            // glslang names a file it cannot include when it compiles.
        }
    }
}

}  // namespace

std::string hlslIncludedText(const std::string& path, const std::string& text) {
    std::set<std::string> seen = {path};
    std::string out;
    collectIncludes(path, text, 0, seen, out);
    return out;
}

std::vector<std::string> hlslEnumNames(const std::string& text) {
    std::vector<std::string> names;
    for (auto it = std::sregex_iterator(text.begin(), text.end(), enumDeclaration());
         it != std::sregex_iterator(); ++it)
        names.push_back((*it)[2].str());
    return names;
}

std::string hlslEnumsAsConstants(const std::string& text, const std::vector<std::string>& known) {
    const std::regex& declaration = enumDeclaration();
    std::string out;
    std::vector<std::string> names = known;
    auto begin = text.cbegin();
    std::smatch m;
    while (std::regex_search(begin, text.cend(), m, declaration)) {
        out.append(begin, m[0].first);
        names.push_back(m[2].str());
        // The constants on the enum's first line, then its line breaks: no later line moves.
        out += enumConstants(m[2].str(), m[3].str(), m[1].matched);
        out += std::string(size_t(countNewlines(m[0].str())), '\n');
        begin = m[0].second;
    }
    out.append(begin, text.cend());
    for (const std::string& name : names)
        out = std::regex_replace(out, std::regex("\\b" + name + "\\s*::\\s*([A-Za-z_]\\w*)"),
                                 name + "_$1");
    return out;
}

namespace {

// A parameter list split at its top-level commas.
std::vector<std::string> splitParameters(const std::string& list) {
    std::vector<std::string> out(1);
    int depth = 0;
    for (char c : list) {
        depth += (c == '(' || c == '<') - (c == ')' || c == '>');
        if (c == ',' && depth == 0)
            out.emplace_back();
        else
            out.back() += c;
    }
    return out;
}

// The name a parameter declares: its last identifier before any ':' semantic or '=' default.
std::string parameterName(const std::string& parameter) {
    const std::string head = parameter.substr(0, parameter.find_first_of(":="));
    static const std::regex last(R"(([A-Za-z_]\w*)\s*$)");
    std::smatch m;
    return std::regex_search(head, m, last) ? m[1].str() : "";
}

}  // namespace

std::string hlslSamplerDefaults(const std::string& text) {
    static const std::regex function(
        R"(\b([A-Za-z_][\w<>]*)\s+([A-Za-z_]\w*)\s*\(((?:[^(){};]|\([^(){};]*\))*=(?:[^(){};]|\([^(){};]*\))*)\)\s*\{)");
    static const std::regex samplerDefault(
        R"(^\s*(?:in\s+|uniform\s+)?(?:SamplerState|SamplerComparisonState|sampler)\s+[A-Za-z_]\w*\s*=)");
    std::string out;
    auto begin = text.cbegin();
    std::smatch m;
    while (std::regex_search(begin, text.cend(), m, function)) {
        const std::vector<std::string> params = splitParameters(m[3].str());
        size_t first = params.size();  // the first parameter with a default
        bool sampler = false;
        for (size_t k = params.size(); k-- > 0 && params[k].find('=') != std::string::npos;) {
            first = k;
            sampler = sampler || std::regex_search(params[k], samplerDefault);
        }
        if (!sampler) {
            out.append(begin, m[0].second);
            begin = m[0].second;
            continue;
        }
        // The definition without its defaults (each `= value` blanked, so that nothing after
        // it on the line moves) ...
        std::string head = m[0].str();
        std::vector<std::string> values;
        for (size_t k = first; k < params.size(); ++k) {
            const size_t eq = params[k].find('=');
            values.push_back(params[k].substr(eq + 1));
            const size_t at = head.find(params[k]);
            head.replace(at + eq, params[k].size() - eq, std::string(params[k].size() - eq, ' '));
        }
        out.append(begin, m[0].first);
        out += head;
        // ... its body to the closing brace ...
        auto at = m[0].second;
        for (int depth = 1; at != text.cend() && depth > 0; ++at)
            depth += (*at == '{') - (*at == '}');
        out.append(m[0].second, at);
        // ... and, on the same line, an overload for each number of defaults left out, which
        // passes them.
        const bool isVoid = m[1].str() == "void";
        for (size_t kept = first; kept < params.size(); ++kept) {
            std::string list, args;
            for (size_t k = 0; k < params.size(); ++k) {
                const std::string sep = k ? ", " : "";
                if (k < kept) list += sep + params[k];
                args += sep + (k < kept ? parameterName(params[k]) : values[k - first]);
            }
            out += " " + m[1].str() + " " + m[2].str() + "(" + list + ") { " +
                   (isVoid ? "" : "return ") + m[2].str() + "(" + args + "); }";
        }
        begin = at;
    }
    out.append(begin, text.cend());
    return out;
}

bool takePragmaOnce(std::string& text) {
    static const std::regex once(R"((^|\n)[ \t]*#[ \t]*pragma[ \t]+once[ \t]*(?=\n|$))");
    if (!std::regex_search(text, once)) return false;
    text = std::regex_replace(text, once, "$1");
    return true;
}

namespace {

// `#include "F"` or `#include <F>` on a line: F, else "".
std::string includeTarget(const std::string& line) {
    static const std::regex include(R"(^[ \t]*#[ \t]*include[ \t]*["<]([^">]+)[">][ \t]*(//.*)?$)");
    std::smatch m;
    return std::regex_match(line, m, include) ? m[1].str() : "";
}

// GLSL's #include, expanded in place, each line's origin recorded.
class GlslIncludes {
  public:
    std::string text;
    std::vector<GlslSpec::LineOrigin> origins;
    bool any = false;

    void expand(const std::string& path, std::string source, size_t depth) {
        if (takePragmaOnce(source)) once_.insert(path);
        std::istringstream in(source);
        std::string line;
        for (int n = 1; std::getline(in, line); ++n) {
            const std::string target = includeTarget(line);
            if (target.empty()) {
                text += line + "\n";
                origins.push_back({path, n});
                continue;
            }
            any = true;
            const std::string name =
                (std::filesystem::path(path).parent_path() / target).lexically_normal().string();
            if (depth + 1 > kMaxIncludeDepth)
                throw InputError(path, "#include", target,
                                 "includes nest more than " + std::to_string(kMaxIncludeDepth) +
                                     " deep (a file that includes itself?)");
            if (once_.count(name)) {  // its #pragma once: included already
                text += "\n";
                origins.push_back({path, n});
                continue;
            }
            std::string sub = normaliseLineEnds(readTextFile(
                name, path + ":" + std::to_string(n), "#include", "GLSL include", kMaxShaderBytes));
            bytes_ += sub.size();
            if (bytes_ > kMaxShaderBytes)
                throw InputError(path, "#include", target,
                                 "the file and its includes pass " +
                                     std::to_string(kMaxShaderBytes >> 20) + " MiB");
            expand(name, std::move(sub), depth + 1);
        }
    }

  private:
    std::set<std::string> once_;
    size_t bytes_ = 0;
};

}  // namespace

void readShaderSource(GlslSpec& spec, const std::string& owner, const std::string& field) {
    std::string text =
        normaliseLineEnds(readTextFile(spec.path, owner, field, "shader file", kMaxShaderBytes));
    spec.origins.clear();
    if (spec.hlsl) {  // glslang includes the HLSL files (methods/shader/hlsl.cpp)
        takePragmaOnce(text);
        spec.included = hlslIncludedText(spec.path, text);
        spec.enums = hlslEnumNames(text + spec.included);
        spec.source = hlslSamplerDefaults(hlslEnumsAsConstants(text, spec.enums));
        return;
    }
    GlslIncludes includes;
    includes.expand(spec.path, text, 0);
    if (!includes.any) {  // the file's own text, byte for byte (its SHA-1 names the study)
        spec.source = std::move(text);
        return;
    }
    spec.source = std::move(includes.text);
    spec.origins = std::move(includes.origins);
}

}  // namespace pgt
