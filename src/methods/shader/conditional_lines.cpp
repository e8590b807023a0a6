// ConditionalLines and blankComments (methods/shader/conditional_lines.h).
#include "methods/shader/conditional_lines.h"

#include <cctype>

namespace pgt {

std::string blankComments(const std::string& text) {
    std::string out = text;
    for (size_t i = 0; i < out.size(); ++i) {
        if (out[i] == '"') {  // a string (an #include's path): kept whole, to its line's end
            for (++i; i < out.size() && out[i] != '"' && out[i] != '\n'; ++i) {
            }
            if (i < out.size() && out[i] == '\n') --i;
            continue;
        }
        if (out[i] != '/' || i + 1 >= out.size()) continue;
        if (out[i + 1] == '/') {
            for (; i < out.size() && out[i] != '\n'; ++i) out[i] = ' ';
        } else if (out[i + 1] == '*') {
            out[i] = out[i + 1] = ' ';
            for (i += 2;
                 i < out.size() && !(out[i] == '*' && i + 1 < out.size() && out[i + 1] == '/'); ++i)
                if (out[i] != '\n') out[i] = ' ';
            if (i < out.size()) out[i] = ' ';
            if (i + 1 < out.size()) out[++i] = ' ';
        }
    }
    return out;
}

namespace {

// The directive of a preprocessor line ("if", "ifdef", ...) and the rest of it; "" when the
// line is no directive.
std::pair<std::string, std::string> directive(const std::string& line) {
    size_t i = line.find_first_not_of(" \t");
    if (i == std::string::npos || line[i] != '#') return {};
    i = line.find_first_not_of(" \t", i + 1);
    if (i == std::string::npos) return {};
    size_t j = i;
    while (j < line.size() && std::isalpha(static_cast<unsigned char>(line[j]))) ++j;
    const size_t rest = line.find_first_not_of(" \t", j);
    std::string tail = rest == std::string::npos ? "" : line.substr(rest);
    while (!tail.empty() && std::isspace(static_cast<unsigned char>(tail.back()))) tail.pop_back();
    return {line.substr(i, j - i), tail};
}

bool identifier(const std::string& s) {
    if (s.empty() || std::isdigit(static_cast<unsigned char>(s[0]))) return false;
    for (char c : s)
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') return false;
    return true;
}

std::string firstWord(const std::string& s) {
    size_t j = 0;
    while (j < s.size() && (std::isalnum(static_cast<unsigned char>(s[j])) || s[j] == '_')) ++j;
    return s.substr(0, j);
}

Branch negate(Branch b) {
    return b == Branch::Active ? Branch::Skipped : b == Branch::Skipped ? Branch::Active : b;
}

}  // namespace

ConditionalLines::ConditionalLines(const std::vector<std::pair<std::string, std::string>>& defines,
                                   bool knowsDefines)
    : knowsDefines_(knowsDefines) {
    for (const auto& [name, value] : defines) names_[name] = Known::Yes;
}

ConditionalLines::Known ConditionalLines::defined(const std::string& name) const {
    if (!knowsDefines_ || name.rfind("GL_", 0) == 0 || name.rfind("__", 0) == 0 ||
        name.rfind("PGT_", 0) == 0)
        return Known::Maybe;
    auto it = names_.find(name);
    return it == names_.end() ? Known::No : it->second;
}

// A number, defined(NAME), defined NAME, each negated with '!' and in parentheses: anything
// else (and anything over 256 characters) is unknown. Read with indices, no recursion.
Branch ConditionalLines::evaluate(const std::string& e) const {
    std::string x;
    for (char c : e)
        if (!std::isspace(static_cast<unsigned char>(c))) x += c;
    if (x.empty() || x.size() > 256) return Branch::Unknown;
    size_t a = 0, b = x.size();
    bool negated = false;
    for (;;) {
        if (a < b && x[a] == '!') {
            negated = !negated, ++a;
        } else if (b - a > 2 && x[a] == '(' && x[b - 1] == ')') {
            ++a, --b;
        } else {
            break;
        }
    }
    const std::string t = x.substr(a, b - a);
    Branch r = Branch::Unknown;
    if (!t.empty() && t.find_first_not_of("0123456789") == std::string::npos) {
        r = t.find_first_not_of('0') == std::string::npos ? Branch::Skipped : Branch::Active;
    } else if (t.rfind("defined", 0) == 0) {
        // defined(NAME), or `defined NAME` (a space after the word in the line as written);
        // `defined_X` is a name of its own.
        std::string name;
        if (t.size() > 9 && t[7] == '(' && t.back() == ')') {
            name = t.substr(8, t.size() - 9);
        } else {
            const size_t at = e.find("defined");
            if (at != std::string::npos && at + 7 < e.size() &&
                std::isspace(static_cast<unsigned char>(e[at + 7])))
                name = t.substr(7);
        }
        if (identifier(name)) {
            const Known k = defined(name);
            r = k == Known::Yes  ? Branch::Active
                : k == Known::No ? Branch::Skipped
                                 : Branch::Unknown;
        }
    }
    return negated ? negate(r) : r;
}

Branch ConditionalLines::here() const {
    const File& f = files_.back();
    if (f.from == Branch::Skipped || f.skipped > 0) return Branch::Skipped;
    return f.from == Branch::Unknown || f.unknown > 0 ? Branch::Unknown : Branch::Active;
}

void ConditionalLines::count(File& f, const Group& g, int sign) const {
    f.skipped += sign * (g.branch == Branch::Skipped);
    f.unknown += sign * (g.branch == Branch::Unknown);
}

Branch ConditionalLines::next(const std::string& line) {
    const Branch around = here();
    const auto [word, rest] = directive(line);
    File& file = files_.back();
    auto open = [&](Branch b) {
        Group g;
        g.branch = b;
        g.taken = b == Branch::Active;
        g.unsure = b == Branch::Unknown;
        file.groups.push_back(g);
        count(file, g, +1);
    };
    auto nextArm = [&](Branch b) {  // #elif / #else
        if (file.groups.empty()) return;
        Group& g = file.groups.back();
        count(file, g, -1);
        g.branch = g.taken                            ? Branch::Skipped
                   : g.unsure && b != Branch::Skipped ? Branch::Unknown
                                                      : b;
        g.taken = g.taken || g.branch == Branch::Active;
        g.unsure = g.unsure || g.branch == Branch::Unknown;
        count(file, g, +1);
    };
    if (word == "if") {
        open(evaluate(rest));
    } else if (word == "ifdef" || word == "ifndef") {
        const std::string name = firstWord(rest);
        const Known k = identifier(name) ? defined(name) : Known::Maybe;
        Branch b = k == Known::Yes  ? Branch::Active
                   : k == Known::No ? Branch::Skipped
                                    : Branch::Unknown;
        open(word == "ifdef" ? b : negate(b));
    } else if (word == "elif") {
        nextArm(evaluate(rest));
    } else if (word == "else") {
        nextArm(Branch::Active);
    } else if (word == "endif") {
        if (!file.groups.empty()) count(file, file.groups.back(), -1), file.groups.pop_back();
    } else if ((word == "define" || word == "undef") && around != Branch::Skipped) {
        const std::string name = firstWord(rest);
        if (identifier(name))
            names_[name] = around == Branch::Unknown ? Known::Maybe
                           : word == "define"        ? Known::Yes
                                                     : Known::No;
    }
    return around;
}

}  // namespace pgt
