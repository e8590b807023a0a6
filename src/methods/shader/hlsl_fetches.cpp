// HLSL fetch counting (methods/shader/hlsl_fetches.h).
#include "methods/shader/hlsl_fetches.h"

#include <algorithm>
#include <cctype>
#include <utility>
#include <vector>

namespace pgt::gl {

namespace {

struct FetchCall {
    const char* name;
    bool method;   // `.Sample(`, or a function `tex2D(`
    size_t coord;  // the coordinate's argument (a method's; a DX9 call is wrapped whole)
    size_t plain;  // the argument count without an offset
};
constexpr FetchCall kFetchCalls[] = {
    {"Sample", true, 1, 2},     {"SampleBias", true, 1, 3}, {"SampleLevel", true, 1, 3},
    {"SampleGrad", true, 1, 4}, {"SampleCmp", true, 1, 3},  {"SampleCmpLevelZero", true, 1, 3},
    {"Load", true, 0, 1},       {"tex2D", false, 1, 2},     {"tex2Dbias", false, 1, 2},
    {"tex2Dlod", false, 1, 2},  {"tex2Dgrad", false, 1, 4},
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

}  // namespace

std::string countFetches(const std::string& text) {
    auto identChar = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
    std::vector<std::pair<size_t, const char*>> inserts;  // (position, text)
    for (const FetchCall& call : kFetchCalls) {
        const std::string name = call.name;
        for (size_t at = text.find(name); at != std::string::npos;
             at = text.find(name, at + name.size())) {
            const size_t end = at + name.size();
            if (end < text.size() && identChar(text[end])) continue;
            if (call.method ? (at == 0 || text[at - 1] != '.')
                            : (at > 0 && (identChar(text[at - 1]) || text[at - 1] == '.')))
                continue;
            size_t open = end;
            while (open < text.size() && (text[open] == ' ' || text[open] == '\t')) ++open;
            if (open >= text.size() || text[open] != '(') continue;
            const auto args = callArguments(text, open);
            if (args.size() != call.plain) continue;  // an offset form, or unbalanced
            if (call.method) {
                inserts.emplace_back(args[call.coord].first, "pgt_counted(");
                inserts.emplace_back(args[call.coord].second, ")");
            } else {
                inserts.emplace_back(at, "pgt_counted(");
                inserts.emplace_back(args.back().second + 1, ")");
            }
        }
    }
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
