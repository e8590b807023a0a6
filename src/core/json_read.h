// Reading untrusted JSON (scene files, a study's study.json): a bounded parse that refuses
// what nlohmann::json would accept but pgt cannot use safely. Nesting deeper than
// kMaxJsonDepth, a key given twice in one object, a number beyond double range and a file
// that is not a regular file are InputErrors naming the file, the field path and the value.
#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>

namespace pgt {

// Deepest nesting accepted (objects and arrays counted together). A scene nests 4 levels;
// 64 leaves room for any hand-written file while keeping every later recursion (dump,
// copy, compare) shallow.
constexpr int kMaxJsonDepth = 64;
// Largest JSON file read (bytes): scenes are a few KB; a bound keeps a stray file cheap.
constexpr std::uintmax_t kMaxJsonFileBytes = 64u << 20;

// Parses `text`; `file` names it in errors. Malformed JSON is reported with its line and
// column; an out-of-range number, a duplicate key or too deep nesting with its field path.
nlohmann::json parseJsonText(const std::string& text, const std::string& file);

// Reads and parses a JSON file (a regular file of at most kMaxJsonFileBytes).
nlohmann::json readJsonFile(const std::string& path);

// Throws InputError(file = `owner`, field, value = path) unless `path` names a regular file
// (not a directory, FIFO or device such as /dev/zero, which readers would block on).
// `what` says what the file is for ("image", "OBJ", "shader").
void requireRegularFile(const std::string& path, const std::string& owner, const std::string& field,
                        const std::string& what);

// Reads a whole regular file (requireRegularFile first); `maxBytes` bounds it.
std::string readTextFile(const std::string& path, const std::string& owner,
                         const std::string& field, const std::string& what,
                         std::uintmax_t maxBytes);

// SHA-1 of a file's bytes as hex (OpenImageIO's SHA1): what a study's identity records of
// every file it reads, so that an edited map, mesh or shader is another study.
std::string fileSha1(const std::string& path);
std::string textSha1(const std::string& text);

}  // namespace pgt
