// Strict JSON field reading with file/field/value errors and "did you mean" suggestions.
#include "core/json_fields.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace pgt {

int editDistance(const std::string& a, const std::string& b) {
    std::vector<int> prev(b.size() + 1), cur(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j) prev[j] = int(j);
    for (size_t i = 1; i <= a.size(); ++i) {
        cur[0] = int(i);
        for (size_t j = 1; j <= b.size(); ++j) {
            int sub = prev[j - 1] + (std::tolower(a[i - 1]) == std::tolower(b[j - 1]) ? 0 : 1);
            cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, sub});
        }
        std::swap(prev, cur);
    }
    return prev[b.size()];
}

std::string nearestName(const std::string& name, const std::vector<std::string>& candidates) {
    std::string best;
    int bestDistance = 1 << 30;
    for (const auto& c : candidates) {
        int d = editDistance(name, c);
        if (d < bestDistance) bestDistance = d, best = c;
    }
    // Accept up to a third of the name's length (at least 2 edits): "theat" -> "theta".
    int limit = std::max<int>(2, int(name.size()) / 3);
    return bestDistance <= limit ? best : std::string();
}

std::string joinNames(const std::vector<std::string>& names) {
    std::string out;
    for (size_t i = 0; i < names.size(); ++i) out += (i ? ", " : "") + names[i];
    return out;
}

std::string shortDump(const Json& j) {
    // Values come from parsed (valid UTF-8) files, but replace rather than throw regardless.
    std::string s = j.dump(-1, ' ', false, Json::error_handler_t::replace);
    if (s.size() > 60) s = s.substr(0, 57) + "...";
    return s;
}

JsonFields::JsonFields(const Json& object, std::string file, std::string path)
    : object_(object), file_(std::move(file)), path_(std::move(path)) {
    if (!object_.is_object())
        throw InputError(file_, path_.empty() ? "(root)" : path_, shortDump(object_),
                         "expected a JSON object");
}

std::string JsonFields::fieldPath(const std::string& key) const {
    return path_.empty() ? key : path_ + "." + key;
}

bool JsonFields::has(const std::string& key) const {
    known_.insert(key);
    return object_.contains(key);
}

const Json& JsonFields::raw(const std::string& key) {
    if (!has(key)) fail(key, "is required");
    return object_.at(key);
}

void JsonFields::fail(const std::string& key, const std::string& message) const {
    std::string value = object_.contains(key) ? shortDump(object_.at(key)) : "";
    throw InputError(file_, fieldPath(key), value, message);
}

void JsonFields::failValue(const std::string& key, const Json& value,
                           const std::string& message) const {
    throw InputError(file_, fieldPath(key), shortDump(value), message);
}

double JsonFields::toNumber(const std::string& key, const Json& v, double lo, double hi) const {
    if (!v.is_number()) failValue(key, v, "expected a number");
    double x = v.get<double>();
    if (!std::isfinite(x) || x < lo || x > hi) {
        std::ostringstream os;
        os << "out of range [" << lo << ", " << hi << "]";
        failValue(key, v, os.str());
    }
    return x;
}

double JsonFields::number(const std::string& key, double fallback, double lo, double hi) {
    if (!has(key)) return fallback;
    return toNumber(key, raw(key), lo, hi);
}

double JsonFields::number(const std::string& key, double lo, double hi) {
    return toNumber(key, raw(key), lo, hi);
}

int JsonFields::integer(const std::string& key, int fallback, int lo, int hi) {
    if (!has(key)) return fallback;
    return integer(key, lo, hi);
}

int JsonFields::integer(const std::string& key, int lo, int hi) {
    const Json& v = raw(key);
    if (!v.is_number_integer() &&
        !(v.is_number_float() && std::floor(v.get<double>()) == v.get<double>()))
        failValue(key, v, "expected an integer");
    return int(toNumber(key, v, lo, hi));
}

bool JsonFields::boolean(const std::string& key, bool fallback) {
    if (!has(key)) return fallback;
    const Json& v = raw(key);
    if (!v.is_boolean()) failValue(key, v, "expected true or false");
    return v.get<bool>();
}

std::string JsonFields::string(const std::string& key, const std::string& fallback) {
    if (!has(key)) return fallback;
    return string(key);
}

std::string JsonFields::string(const std::string& key) {
    const Json& v = raw(key);
    if (!v.is_string()) failValue(key, v, "expected a string");
    return v.get<std::string>();
}

std::string JsonFields::choice(const std::string& key, const std::vector<std::string>& choices,
                               const std::string& fallback) {
    std::string s = has(key) ? string(key) : fallback;
    if (std::find(choices.begin(), choices.end(), s) != choices.end()) return s;
    std::string hint = nearestName(s, choices);
    fail(key, "unknown value; expected one of " + joinNames(choices) +
                  (hint.empty() ? "" : " (did you mean \"" + hint + "\"?)"));
}

std::vector<double> JsonFields::numbers(const std::string& key, size_t count, double lo,
                                        double hi) {
    const Json& v = raw(key);
    if (!v.is_array() || v.size() != count)
        failValue(key, v, "expected an array of " + std::to_string(count) + " numbers");
    std::vector<double> out;
    for (const auto& e : v) out.push_back(toNumber(key, e, lo, hi));
    return out;
}

std::vector<int> JsonFields::integers(const std::string& key, size_t count, int lo, int hi) {
    const Json& v = raw(key);
    if (!v.is_array() || v.size() != count)
        failValue(key, v, "expected an array of " + std::to_string(count) + " integers");
    std::vector<int> out;
    for (const auto& e : v) {
        if (!e.is_number_integer()) failValue(key, v, "expected integers");
        out.push_back(int(toNumber(key, e, lo, hi)));
    }
    return out;
}

void JsonFields::finish(const std::vector<std::string>& alsoAllowed) const {
    std::vector<std::string> known(known_.begin(), known_.end());
    known.insert(known.end(), alsoAllowed.begin(), alsoAllowed.end());
    for (auto it = object_.begin(); it != object_.end(); ++it) {
        if (std::find(known.begin(), known.end(), it.key()) != known.end()) continue;
        std::string hint = nearestName(it.key(), known);
        throw InputError(
            file_, fieldPath(it.key()), shortDump(it.value()),
            "unknown key" + (hint.empty() ? std::string() : " (did you mean \"" + hint + "\"?)"));
    }
}

}  // namespace pgt
