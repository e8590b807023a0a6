// Bounded JSON reading through nlohmann::json's SAX interface: its parser is iterative, so
// a DOM built here, one level at a time, can stop at kMaxJsonDepth before anything recurses.
#include "core/json_read.h"

#include <OpenImageIO/hash.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <vector>

#include "core/error.h"
#include "core/json_fields.h"

namespace pgt {

namespace fs = std::filesystem;

namespace {

// Builds the DOM like nlohmann's own SAX DOM parser, and keeps the path of the value being
// read so that every refusal names its field ("camera.theta", "methods[2]").
class BoundedDomBuilder {
  public:
    using Json = nlohmann::json;

    explicit BoundedDomBuilder(std::string file) : file_(std::move(file)) {}

    bool null() { return value(Json(nullptr)); }
    bool boolean(bool v) { return value(Json(v)); }
    bool number_integer(Json::number_integer_t v) { return value(Json(v)); }
    bool number_unsigned(Json::number_unsigned_t v) { return value(Json(v)); }
    bool number_float(Json::number_float_t v, const Json::string_t&) { return value(Json(v)); }
    bool string(Json::string_t& v) { return value(Json(std::move(v))); }
    bool binary(Json::binary_t& v) { return value(Json(std::move(v))); }
    bool start_object(std::size_t) { return open(Json::object()); }
    bool start_array(std::size_t) { return open(Json::array()); }
    bool end_object() { return close(); }
    bool end_array() { return close(); }

    bool key(Json::string_t& k) {
        Json& object = *stack_.back().node;
        stack_.back().key = k;
        if (object.contains(k)) {
            refusal_.emplace(file_, pathOfNext(), "", "key given twice in one object");
            return false;
        }
        pending_ = &object[k];
        return true;
    }

    bool parse_error(std::size_t position, const std::string& token,
                     const nlohmann::detail::exception& ex) {
        position_ = position;
        if (ex.id == 406) {  // out_of_range.406: a number beyond double (1e400)
            refusal_.emplace(file_, pathOfNext(), token, "number out of range (beyond double)");
        } else {
            std::string what = ex.what();
            auto at = what.find("parse error");
            message_ = at == std::string::npos ? what : what.substr(at);
        }
        return false;
    }

    // Throws the refusal recorded by a handler that returned false, if any.
    void rethrow() const {
        if (refusal_) throw *refusal_;
    }
    const std::string& parseMessage() const { return message_; }
    std::size_t position() const { return position_; }
    Json take() { return std::move(root_); }

  private:
    struct Level {
        Json* node;
        std::string key;  // objects: the member being read
    };

    // Where the next value goes: the root, the end of an array, or the pending member.
    Json* place(Json&& v) {
        if (stack_.empty()) {
            root_ = std::move(v);
            return &root_;
        }
        Json& top = *stack_.back().node;
        if (top.is_array()) {
            top.push_back(std::move(v));
            return &top.back();
        }
        *pending_ = std::move(v);
        return pending_;
    }
    bool value(Json&& v) {
        place(std::move(v));
        return true;
    }
    bool open(Json&& container) {
        if (int(stack_.size()) >= kMaxJsonDepth) {
            std::string path = pathOfNext();
            refusal_.emplace(file_, path.empty() ? "(root)" : path, "",
                             "nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
            return false;
        }
        Json* node = place(std::move(container));
        stack_.push_back({node, ""});
        return true;
    }
    bool close() {
        stack_.pop_back();
        return true;
    }
    // Field path of the value about to be read.
    std::string pathOfNext() const {
        std::string path;
        for (size_t i = 0; i < stack_.size(); ++i) {
            const Json& node = *stack_[i].node;
            bool last = i + 1 == stack_.size();
            if (node.is_array()) {
                size_t index = node.empty() ? 0 : node.size() - 1;
                if (last) index = node.size();
                // append(), not "[" + ...: GCC 12 warns falsely (-Wrestrict) on the latter.
                path.append("[").append(std::to_string(index)).append("]");
            } else {
                if (!path.empty()) path.append(".");
                path.append(stack_[i].key);
            }
        }
        return path;
    }

    std::string file_;
    Json root_;
    std::vector<Level> stack_;
    Json* pending_ = nullptr;
    std::optional<InputError> refusal_;  // why a handler stopped the parse, if it did
    std::string message_;
    std::size_t position_ = 0;
};

}  // namespace

nlohmann::json parseJsonText(const std::string& text, const std::string& file) {
    // The bound of a JSON file holds for JSON text handed over whole (a Python dict) too.
    if (text.size() > kMaxJsonFileBytes)
        throw InputError(file, "", "",
                         "JSON text of " + std::to_string(text.size()) + " bytes, more than the " +
                             std::to_string(kMaxJsonFileBytes) + " accepted (a scene is a few KB)");
    BoundedDomBuilder builder(file);
    bool ok = nlohmann::json::sax_parse(text, &builder);
    if (ok) return builder.take();
    builder.rethrow();
    // Malformed JSON: translate the byte offset into line and column for people.
    size_t offset = std::min<size_t>(builder.position(), text.size());
    int line = 1, column = 1;
    for (size_t i = 0; i + 1 < offset; ++i) {
        if (text[i] == '\n')
            ++line, column = 1;
        else
            ++column;
    }
    throw InputError(file, "line " + std::to_string(line) + ", column " + std::to_string(column),
                     "", "malformed JSON: " + builder.parseMessage());
}

void requireRegularFile(const std::string& path, const std::string& owner, const std::string& field,
                        const std::string& what) {
    std::error_code ec;
    auto status = fs::status(path, ec);
    const std::string value = owner == path ? "" : path;  // the file itself: named once
    if (ec || !fs::exists(status))
        throw InputError(owner, field, value, "cannot open " + what + ": no such file");
    if (!fs::is_regular_file(status))
        throw InputError(
            owner, field, value,
            "is not a regular file (a directory, device or pipe); a " + what + " must be a file");
}

std::string readTextFile(const std::string& path, const std::string& owner,
                         const std::string& field, const std::string& what,
                         std::uintmax_t maxBytes) {
    requireRegularFile(path, owner, field, what);
    std::error_code ec;
    std::uintmax_t size = fs::file_size(path, ec);
    if (!ec && size > maxBytes)
        throw InputError(owner, field, owner == path ? "" : path,
                         what + " is " + std::to_string(size) + " bytes, more than the " +
                             std::to_string(maxBytes) + " accepted");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(owner, field, owner == path ? "" : path, "cannot open " + what);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

std::string textSha1(const std::string& text) {
    return OIIO::SHA1::digest(text.data(), text.size());
}

std::string fileSha1(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    OIIO::SHA1 sha;
    std::vector<char> buf(1 << 20);
    while (in) {
        in.read(buf.data(), std::streamsize(buf.size()));
        if (in.gcount() > 0) sha.append(buf.data(), size_t(in.gcount()));
    }
    return sha.digest();
}

nlohmann::json readJsonFile(const std::string& path) {
    return parseJsonText(readTextFile(path, path, "", "JSON file", kMaxJsonFileBytes), path);
}

}  // namespace pgt
