// Reading a glTF file (mesh/gltf_file.h): tinygltf parses; pgt bounds the file and its JSON
// first and confines every buffer tinygltf reads to the asset's folder.
#include "mesh/gltf_file.h"

#include <cstring>
#include <filesystem>
#include <fstream>

#include "core/json_read.h"

namespace pgt {

namespace fs = std::filesystem;
using Json = nlohmann::json;

namespace {

constexpr std::uintmax_t kMaxFileBytes = std::uintmax_t(1) << 30;
using Fail = GltfFail;

// Buffers and images tinygltf reads through these: bounded in size, and a uri may not
// leave the asset's folder (no absolute path, no ".." above it).
struct FsGuard {
    fs::path folder;
    std::string refused;  // the first uri refused, for the error message
};

// tinygltf calls these from C: they must not throw (a uri too long for a path is just absent).
bool fileExists(const std::string& path, void*) {
    std::error_code ec;
    return fs::is_regular_file(path, ec);
}
std::string expandNothing(const std::string& path, void*) { return path; }  // no ~ or $VAR

bool readGuarded(std::vector<unsigned char>* out, std::string* err, const std::string& path,
                 void* user) {
    auto* guard = static_cast<FsGuard*>(user);
    const fs::path rel = fs::path(path).lexically_normal().lexically_relative(guard->folder);
    if (fs::path(path).is_absolute() == false || rel.empty() || *rel.begin() == ".." ||
        rel.is_absolute()) {
        if (guard->refused.empty()) guard->refused = path;
        if (err) *err += "uri leaves the asset's folder: " + path;
        return false;
    }
    std::error_code ec;
    if (!fs::is_regular_file(path, ec) || fs::file_size(path, ec) > kMaxFileBytes || ec) {
        if (err) *err += "cannot read " + path;
        return false;
    }
    std::ifstream f(path, std::ios::binary);
    out->assign(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
    return bool(f) || f.eof();
}

// Images are not pgt's business (the height map is the scene's): keep them undecoded.
bool skipImage(tinygltf::Image*, const int, std::string*, std::string*, int, int,
               const unsigned char*, int, void*) {
    return true;
}

// The JSON of a .gltf (the whole file) or a .glb (its first chunk, bounds checked).
std::string jsonOf(const std::string& bytes, bool binary, const Fail& fail) {
    if (!binary) return bytes;
    auto word = [&](size_t at) {
        uint32_t w = 0;
        if (at + 4 <= bytes.size()) std::memcpy(&w, bytes.data() + at, 4);
        return w;
    };
    const uint32_t length = word(12);
    if (bytes.size() < 20 || word(16) != 0x4E4F534Au || double(length) + 20 > double(bytes.size()))
        fail("the GLB's first chunk is not JSON within the file (" + std::to_string(bytes.size()) +
             " bytes, chunk length " + std::to_string(length) + ")");
    return bytes.substr(20, length);
}

// What tinygltf would accept but pgt cannot read or use safely, checked on pgt's bounded
// JSON reader first: nesting deeper than 64 (tinygltf's parser recurses without a bound), a
// version other than 2, required compression extensions, a buffer uri that is absolute.
void precheck(const std::string& json, const std::string& path, const Fail& fail) {
    Json doc;
    try {
        doc = parseJsonText(json, path);
    } catch (const InputError& e) {
        fail("not a readable glTF 2.0 file: " + printable(e.what(), 300));
    }
    const Json* version = doc.is_object() && doc.contains("asset") && doc["asset"].is_object() &&
                                  doc["asset"].contains("version")
                              ? &doc["asset"]["version"]
                              : nullptr;
    if (version && version->is_string() && version->get<std::string>().rfind("2.", 0) != 0)
        fail("asset.version is \"" + printable(version->get<std::string>(), 20) +
             "\"; pgt reads glTF 2.0");
    if (doc.contains("extensionsRequired") && doc["extensionsRequired"].is_array())
        for (const Json& ext : doc["extensionsRequired"])
            if (ext == "KHR_draco_mesh_compression" || ext == "EXT_meshopt_compression")
                fail("the asset requires " + ext.get<std::string>() +
                     "; pgt reads uncompressed buffers");
    if (doc.contains("buffers") && doc["buffers"].is_array())
        for (size_t k = 0; k < doc["buffers"].size(); ++k) {
            const Json& b = doc["buffers"][k];
            if (!b.is_object() || !b.contains("uri") || !b["uri"].is_string()) continue;
            const std::string uri = b["uri"].get<std::string>();
            if (uri.rfind("data:", 0) != 0 &&
                (fs::path(uri).is_absolute() || uri.find("://") != std::string::npos))
                fail("buffer " + std::to_string(k) + "'s uri \"" + printable(uri, 80) +
                     "\" is not a path relative to the asset");
        }
}

}  // namespace

tinygltf::Model readGltfModel(const std::string& path, const GltfFail& fail, std::string* sha1) {
    const std::string bytes =
        readTextFile(path, fail.sceneFile, fail.field, "glTF file", kMaxFileBytes);
    *sha1 = textSha1(bytes);
    const bool binary = bytes.rfind("glTF", 0) == 0;
    precheck(jsonOf(bytes, binary, fail), path, fail);
    FsGuard guard{fs::absolute(path).parent_path().lexically_normal(), {}};
    tinygltf::TinyGLTF loader;
    loader.SetFsCallbacks({fileExists, expandNothing, readGuarded, nullptr, &guard});
    loader.SetImageLoader(skipImage, nullptr);
    tinygltf::Model model;
    std::string err, warn;
    const std::string folder = guard.folder.string();
    const bool ok =
        binary ? loader.LoadBinaryFromMemory(&model, &err, &warn,
                                             reinterpret_cast<const unsigned char*>(bytes.data()),
                                             unsigned(bytes.size()), folder)
               : loader.LoadASCIIFromString(&model, &err, &warn, bytes.data(),
                                            unsigned(bytes.size()), folder);
    if (!guard.refused.empty())
        fail("a uri leaves the asset's folder: " +
             fs::path(guard.refused).lexically_normal().lexically_relative(guard.folder).string());
    if (!ok) {
        while (!err.empty() && (err.back() == '\n' || err.back() == ' ')) err.pop_back();
        fail("not a readable glTF 2.0 file: " +
             (err.empty() ? std::string("tinygltf gave no reason") : printable(err, 160)));
    }
    return model;
}

}  // namespace pgt
