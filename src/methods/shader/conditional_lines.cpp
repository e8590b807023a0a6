// ConditionalLines and blankComments (methods/shader/conditional_lines.h).
#include "methods/shader/conditional_lines.h"

#include <cctype>

namespace pgt {

std::string blankComments(const std::string& text) {
    std::string out = text;
    for (size_t i = 0; i < out.size(); ++i) {
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

// A number, defined(NAME), defined NAME, NAME's definedness negated with '!': anything else
// is unknown.
Branch ConditionalLines::evaluate(const std::string& e) const {
    std::string x;
    for (char c : e)
        if (!std::isspace(static_cast<unsigned char>(c))) x += c;
    if (x.empty()) return Branch::Unknown;
    if (x[0] == '!') return negate(evaluate(x.substr(1)));
    if (x.size() > 2 && x.front() == '(' && x.back() == ')')
        return evaluate(x.substr(1, x.size() - 2));
    if (x.find_first_not_of("0123456789") == std::string::npos)
        return x.find_first_not_of('0') == std::string::npos ? Branch::Skipped : Branch::Active;
    if (x.rfind("defined", 0) == 0) {
        std::string name = x.substr(7);
        if (name.size() > 2 && name.front() == '(' && name.back() == ')')
            name = name.substr(1, name.size() - 2);
        if (!identifier(name)) return Branch::Unknown;
        const Known k = defined(name);
        return k == Known::Yes  ? Branch::Active
               : k == Known::No ? Branch::Skipped
                                : Branch::Unknown;
    }
    return Branch::Unknown;
}

Branch ConditionalLines::here() const {
    Branch b = Branch::Active;
    for (const Group& g : stacks_.back()) {
        if (g.branch == Branch::Skipped) return Branch::Skipped;
        if (g.branch == Branch::Unknown) b = Branch::Unknown;
    }
    return b;
}

Branch ConditionalLines::next(const std::string& line) {
    const Branch around = here();
    const auto [word, rest] = directive(line);
    auto& stack = stacks_.back();
    auto open = [&](Branch b) {
        Group g;
        g.branch = b;
        g.taken = b == Branch::Active;
        g.unsure = b == Branch::Unknown;
        stack.push_back(g);
    };
    auto nextArm = [&](Branch b) {  // #elif / #else
        if (stack.empty()) return;
        Group& g = stack.back();
        g.branch = g.taken                            ? Branch::Skipped
                   : g.unsure && b != Branch::Skipped ? Branch::Unknown
                                                      : b;
        g.taken = g.taken || g.branch == Branch::Active;
        g.unsure = g.unsure || g.branch == Branch::Unknown;
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
        if (!stack.empty()) stack.pop_back();
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
