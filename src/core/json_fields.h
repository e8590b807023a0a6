// Strict reading of JSON objects for input files: every field is typed and range-checked,
// every unknown key is rejected with the nearest known key suggested, and every error names
// the file, the field path and the value (core/error.h). The ranges callers give (1e-6 to
// 1e6 for sizes, +-1e3 UV for a displacement, ...) bound typos and keep arithmetic finite;
// none is a physical limit.
#pragma once

#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "core/error.h"

namespace pgt {

using Json = nlohmann::json;

// Edit distance, for "did you mean" suggestions.
int editDistance(const std::string& a, const std::string& b);
// The closest candidate within a small distance, or "" when none is close.
std::string nearestName(const std::string& name, const std::vector<std::string>& candidates);
std::string joinNames(const std::vector<std::string>& names);
std::string shortDump(const Json& j);

class JsonFields {
  public:
    // `path` is this object's field path ("camera", "methods[2]"); "" for the root.
    JsonFields(const Json& object, std::string file, std::string path);

    bool has(const std::string& key) const;
    const Json& raw(const std::string& key);  // marks the key used; must exist
    std::string fieldPath(const std::string& key) const;

    double number(const std::string& key, double fallback, double lo, double hi);
    double number(const std::string& key, double lo, double hi);  // required
    int integer(const std::string& key, int fallback, int lo, int hi);
    int integer(const std::string& key, int lo, int hi);
    bool boolean(const std::string& key, bool fallback);
    std::string string(const std::string& key, const std::string& fallback);
    std::string string(const std::string& key);
    // One of `choices`, with a suggestion when misspelt.
    std::string choice(const std::string& key, const std::vector<std::string>& choices,
                       const std::string& fallback);
    std::vector<double> numbers(const std::string& key, size_t count, double lo, double hi);
    std::vector<int> integers(const std::string& key, size_t count, int lo, int hi);

    // Throws for any key that no getter asked for, suggesting the nearest known key.
    void finish(const std::vector<std::string>& alsoAllowed = {}) const;

    [[noreturn]] void fail(const std::string& key, const std::string& message) const;
    [[noreturn]] void failValue(const std::string& key, const Json& value,
                                const std::string& message) const;
    const std::string& file() const { return file_; }
    const std::string& path() const { return path_; }

  private:
    double toNumber(const std::string& key, const Json& v, double lo, double hi) const;
    const Json& object_;
    std::string file_, path_;
    mutable std::set<std::string> known_;  // every key asked for, present or not
};

}  // namespace pgt
