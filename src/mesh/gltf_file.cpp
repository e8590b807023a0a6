// Reading a glTF file (mesh/gltf_file.h): tinygltf parses; pgt bounds the file and its JSON
// first, estimates the memory of the whole load before a buffer is read or decoded, and
// confines every buffer tinygltf reads to the asset's folder.
#include "mesh/gltf_file.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "core/format.h"
#include "core/json_read.h"
#include "core/memory.h"

namespace pgt {

namespace fs = std::filesystem;
using Json = nlohmann::json;

namespace {

constexpr std::uintmax_t kMaxFileBytes = std::uintmax_t(1) << 30;
using Fail = GltfFail;

// Building the drawn primitive (mesh/gltf_mesh.cpp: the accessors read as doubles, the
// attributes, MikkTSpace's frames and split, the world mesh, the welded cage), beside the
// buffers, measured at its peak and rounded up by about a third: per POSITION element 400
// bytes (302 measured: 2 M vertices with NORMAL and TANGENT kept, one triangle); per index (a
// triangle's corner) 50 bytes where corners share their vertices (26 measured: a 700 x 700
// grid with its TANGENT, or "frames": "pgt"), 450 where each corner may become a vertex of its
// own: flat normals without NORMAL, MikkTSpace splitting vertices (355 measured: the grid
// without NORMAL and with random UVs).
constexpr double kBytesPerVertex = 400;
constexpr double kBytesPerCorner = 50;
constexpr double kBytesPerSplitCorner = 450;
// tinygltf keeps "extras" and "extensions" as trees of tinygltf::Value, one (in a map node
// for an object's member) per JSON value; an object in a top-level array becomes one of its
// structs (a material, the largest, 2 KB), an object inside one may (a primitive, an
// animation's channel), each in a vector that may hold as much again while it grows.
constexpr double kBytesPerExtraValue = sizeof(tinygltf::Value) + 80;
constexpr double kBytesPerTopObject =
    2.0 * double(std::max({sizeof(tinygltf::Material), sizeof(tinygltf::Camera),
                           sizeof(tinygltf::Light), sizeof(tinygltf::Node)}));
constexpr double kBytesPerInnerObject =
    2.0 * double(std::max({sizeof(tinygltf::Primitive), sizeof(tinygltf::AnimationChannel),
                           sizeof(tinygltf::AnimationSampler)}));

// Buffers and images tinygltf reads through these: bounded in size, and a uri may not
// leave the asset's folder (no absolute path, no ".." above it).
struct FsGuard {
    fs::path folder;
    std::string refused;         // the first uri refused, for the error message
    std::uintmax_t maxRead = 0;  // the largest byteLength of a buffer kept in a file
};

// tinygltf calls these from C: they must not throw (a uri too long for a path is just absent).
bool fileExists(const std::string& path, void*) {
    std::error_code ec;
    return fs::is_regular_file(path, ec);
}
std::string expandNothing(const std::string& path, void*) { return path; }  // no ~ or $VAR

// A file larger than every buffer's byteLength is not read (tinygltf would read it whole and
// only then compare); images, never decoded, are read only within that bound.
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
    const std::uintmax_t size = fs::is_regular_file(path, ec) ? fs::file_size(path, ec) : 0;
    if (ec || size > kMaxFileBytes || size > guard->maxRead) {
        if (err)
            *err += ec ? "cannot read " + path
                       : path + " is " + std::to_string(size) +
                             " bytes, more than any buffer's byteLength (" +
                             std::to_string(guard->maxRead) + "): not read";
        return false;
    }
    out->resize(size_t(size));
    std::ifstream f(path, std::ios::binary);
    return size == 0 || bool(f.read(reinterpret_cast<char*>(out->data()), std::streamsize(size)));
}

// Images are not pgt's business (the height map is the scene's): keep them undecoded.
bool skipImage(tinygltf::Image*, const int, std::string*, std::string*, int, int,
               const unsigned char*, int, void*) {
    return true;
}

// The asset's size: a regular file of at most 1 GiB.
std::uintmax_t assetSize(const std::string& path, const Fail& fail) {
    requireRegularFile(path, fail.sceneFile, fail.field, "glTF file");
    std::error_code ec;
    const std::uintmax_t size = fs::file_size(path, ec);
    if (ec) fail("cannot open glTF file");
    if (size > kMaxFileBytes)
        fail("glTF file is " + std::to_string(size) + " bytes, more than the " +
             std::to_string(kMaxFileBytes) + " accepted");
    return size;
}

// `count` bytes of the file from `offset`, read in one piece (no stream growing by doubling).
std::string readRange(const std::string& path, std::uintmax_t offset, std::uintmax_t count,
                      const Fail& fail) {
    std::string out(size_t(count), '\0');
    std::ifstream f(path, std::ios::binary);
    if (!f) fail("cannot open glTF file");
    if (!f.seekg(std::streamoff(offset)) || !f.read(out.data(), std::streamsize(count)))
        fail("cannot read glTF file (" + std::to_string(count) + " bytes from byte " +
             std::to_string(offset) + ")");
    return out;
}

// A .glb's JSON (its first chunk, bounds checked against the file's size), read alone.
std::string glbJson(const std::string& path, const std::string& head, std::uintmax_t size,
                    const Fail& fail) {
    auto word = [&](size_t at) {
        uint32_t w = 0;
        if (at + 4 <= head.size()) std::memcpy(&w, head.data() + at, 4);
        return w;
    };
    const uint32_t length = word(12);
    if (size < 20 || word(16) != 0x4E4F534Au || double(length) + 20 > double(size))
        fail("the GLB's first chunk is not JSON within the file (" + std::to_string(size) +
             " bytes, chunk length " + std::to_string(length) + ")");
    return readRange(path, 20, length, fail);
}

// What the load needs at its peaks (bytes): tinygltf's parse holds the file, its JSON document
// (pgt's own is freed before), the buffers and the largest transient (a data: URI's copy and
// decoded bytes, an image file read and dropped, the lexer's copy of the longest string);
// building the primitive holds the buffers and the primitive's vertices and corners.
struct LoadEstimate {
    double file = 0, json = 0, buffers = 0, transient = 0;
    double vertices = 0, corners = 0, cornerBytes = kBytesPerSplitCorner;
    double bytes() const {
        return std::max(file + json + buffers + transient,
                        buffers + vertices * kBytesPerVertex + corners * cornerBytes);
    }
    std::string what() const {
        auto mb = [](double b) { return formatNumber(std::ceil(b / (1 << 20)), 15) + " MB"; };
        std::string parts = "its file " + mb(file) + ", its JSON parsed " + mb(json);
        if (buffers > 0) parts += ", buffers " + mb(buffers);
        if (vertices > 0)
            parts += ", a primitive of " + formatNumber(vertices, 15) + " vertices and " +
                     formatNumber(std::floor(corners / 3), 15) + " triangles";
        return "reading the glTF asset (" + parts + ")";
    }
};

// The memory a JSON text takes once parsed, counted in one pass that allocates nothing but a
// stack of open containers (the text is checked afterwards, by pgt's bounded reader): a
// document's 16 bytes a value, its nodes and strings, tinygltf's copies of the strings and of
// number arrays (an array's element: 48 bytes more, with the vectors' spare capacity), its
// structs and its Value trees under "extras" and "extensions" (2 M numbers in an accessor's
// min: 97 MB measured, 128 estimated). `longest` gets the longest string's length.
double jsonCost(const std::string& text, double* longest) {
    struct Open {
        bool array, extra;
    };
    std::vector<Open> open;
    double bytes = 0;
    bool extraNext = false;  // the value of an "extras" or "extensions" key comes next
    auto value = [&](double own) {
        const bool extra = extraNext || (!open.empty() && open.back().extra);
        extraNext = false;
        bytes += 16 + own + (extra ? kBytesPerExtraValue : 0) +
                 (!open.empty() && open.back().array ? 48 : 0);
        return extra;
    };
    for (size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (c == '"') {
            size_t end = i + 1;
            while (end < text.size() && text[end] != '"') end += text[end] == '\\' ? 2 : 1;
            const size_t len = std::min(end, text.size()) - i - 1;
            *longest = std::max(*longest, double(len));
            const size_t next = text.find_first_not_of(" \t\r\n", end + 1);
            if (next < text.size() && text[next] == ':') {  // a key: a map node and its copy
                bytes += 96 + 2 * double(len);
                extraNext = text.compare(i + 1, len, "extras") == 0 ||
                            text.compare(i + 1, len, "extensions") == 0;
            } else {
                value(2 * (48 + double(len)));  // the document's string and tinygltf's copy
            }
            i = end;
        } else if (c == '{' || c == '[') {
            const double structBytes = open.size() == 2 ? kBytesPerTopObject : kBytesPerInnerObject;
            const bool extra = value(64 + (c == '{' ? structBytes : 0));
            open.push_back({c == '[', extra});
        } else if ((c == '}' || c == ']') && !open.empty()) {
            open.pop_back();
        } else if (c == '-' || (c >= '0' && c <= '9') || c == 't' || c == 'f' || c == 'n') {
            value(0);
            while (i + 1 < text.size() && !std::strchr(",]} \t\r\n", text[i + 1])) ++i;
        }
    }
    return bytes;
}

// doc[key] where doc is an object that has it; (*list)[index] where list is an array that long
// and index a non-negative integer in it; else nullptr (the JSON is untrusted: any type).
const Json* member(const Json* doc, const char* key) {
    if (!doc || !doc->is_object()) return nullptr;
    auto it = doc->find(key);
    return it == doc->end() ? nullptr : &*it;
}
const Json* element(const Json* list, long long index) {
    if (!list || !list->is_array() || index < 0 || size_t(index) >= list->size()) return nullptr;
    return &(*list)[size_t(index)];
}
const Json* element(const Json* list, const Json* index) {
    return index && index->is_number_integer() ? element(list, index->get<long long>()) : nullptr;
}
double count(const Json* value) {  // a non-negative number, else 0
    return value && value->is_number() && value->get<double>() > 0 ? value->get<double>() : 0;
}

// The primitive `which` selects, found in the JSON as selectPrimitive (gltf_mesh.cpp) finds it
// in tinygltf's model; nullptr where the selection does not resolve (selectPrimitive says why).
const Json* selectedPrimitive(const Json& doc, const GltfSelection& which) {
    auto named = [&](const char* list, const std::string& name) {
        long long found = -1, matches = 0;
        const Json* all = member(&doc, list);
        for (size_t k = 0; all && all->is_array() && k < all->size(); ++k)
            if (const Json* n = member(&(*all)[k], "name"); n && *n == name)
                found = (found < 0 ? static_cast<long long>(k) : found), ++matches;
        return matches == 1 ? found : -2;
    };
    const long long node = which.nodeName.empty() ? which.node : named("nodes", which.nodeName);
    long long mesh = which.mesh;
    if (node == -2) return nullptr;
    if (node >= 0 && !which.meshGiven) {
        const Json* m = member(element(member(&doc, "nodes"), node), "mesh");
        mesh = m && m->is_number_integer() ? m->get<long long>() : -1;
    }
    if (!which.meshName.empty()) mesh = named("meshes", which.meshName);
    return element(member(element(member(&doc, "meshes"), mesh), "primitives"), which.primitive);
}

// The selected primitive's vertices and corners for the estimate; more than 2^24 triangles
// are refused here, from the accessor's count, before a buffer is read. Corners keep sharing
// their vertices with NORMAL and frames that do not split (the asset's TANGENT, pgt's).
void checkPrimitive(const Json& doc, const GltfSelection& which, MeshFrames frames,
                    const Fail& fail, LoadEstimate& est) {
    const Json* prim = selectedPrimitive(doc, which);
    const Json* accessors = member(&doc, "accessors");
    const Json* attributes = member(prim, "attributes");
    const Json* position = member(attributes, "POSITION");
    const Json* indices = member(prim, "indices");
    est.vertices = count(member(element(accessors, position), "count"));
    est.corners = indices ? count(member(element(accessors, indices), "count")) : est.vertices;
    if (member(attributes, "NORMAL") &&
        (frames == MeshFrames::Pgt ||
         (frames == MeshFrames::Asset && member(attributes, "TANGENT"))))
        est.cornerBytes = kBytesPerCorner;
    const double triangles = std::floor(est.corners / 3);
    if (triangles > double(kMaxGltfTriangles)) {
        const Json* acc = indices ? indices : position;
        fail("the primitive has " + formatNumber(triangles, 15) + " triangles (more than 2^24: " +
             "accessor " + acc->dump() + " (" + (indices ? "indices" : "POSITION") +
             ") has count " + formatNumber(est.corners, 15) + ")");
    }
}

// A uri that holds a NUL, raw or as %00, would be read cut at it (C's paths end there).
void checkUri(const std::string& uri, const std::string& field, const Fail& fail) {
    if (uri.find('\0') != std::string::npos || uri.find("%00") != std::string::npos)
        fail(field + " = \"" + printable(uri, 80) +
             "\" holds a NUL character (raw or %00): a path would end there");
}

// Buffers (and images) for the estimate, and their uris: a buffer's relative, none with a NUL.
// A data: URI's text is in the JSON; tinygltf copies it and decodes it beside the copy.
void checkBuffers(const Json& doc, const Fail& fail, LoadEstimate& est, FsGuard& guard) {
    bool imageFiles = false;
    for (const std::string list : {"buffers", "images"}) {
        const Json* all = member(&doc, list.c_str());
        for (size_t k = 0; all && all->is_array() && k < all->size(); ++k) {
            const Json* uri = member(&(*all)[k], "uri");
            const double length = list == "buffers" ? count(member(&(*all)[k], "byteLength")) : 0;
            est.buffers += length;
            if (!uri || !uri->is_string()) continue;
            const std::string& text = uri->get_ref<const std::string&>();
            checkUri(text, list + "[" + std::to_string(k) + "].uri", fail);
            const double chars = double(text.size());
            if (text.rfind("data:", 0) == 0) {
                est.transient = std::max(est.transient, chars + 2 * std::max(length, 0.75 * chars));
                continue;
            }
            guard.maxRead = std::max(guard.maxRead, std::uintmax_t(std::min(length, 1e18)));
            imageFiles = imageFiles || list == "images";
            if (list == "buffers" &&
                (fs::path(text).is_absolute() || text.find("://") != std::string::npos))
                fail("buffer " + std::to_string(k) + "'s uri \"" + printable(text, 80) +
                     "\" is not a path relative to the asset");
        }
    }
    if (imageFiles)  // an image file is read (at most maxRead bytes) and dropped
        est.transient = std::max(est.transient, double(guard.maxRead));
}

// The glTF version and the extensions the asset requires: pgt implements
// KHR_mesh_quantization (any component type, normalized or not, is read as glTF defines it)
// and no other; glTF says a reader must refuse an asset that requires what it lacks.
void checkRequired(const Json& doc, const Fail& fail) {
    const Json* version = member(member(&doc, "asset"), "version");
    if (version && version->is_string() && version->get<std::string>().rfind("2.", 0) != 0)
        fail("asset.version is \"" + printable(version->get<std::string>(), 20) +
             "\"; pgt reads glTF 2.0");
    const Json* required = member(&doc, "extensionsRequired");
    for (size_t k = 0; required && required->is_array() && k < required->size(); ++k) {
        const Json& ext = (*required)[k];
        const std::string field = "extensionsRequired[" + std::to_string(k) + "]";
        if (!ext.is_string()) fail(field + " is not a string (an extension's name)");
        const std::string& name = ext.get_ref<const std::string&>();
        if (name == "KHR_draco_mesh_compression" || name == "EXT_meshopt_compression")
            fail(field + ": the asset requires " + name + "; pgt reads uncompressed buffers");
        if (name != "KHR_mesh_quantization")
            fail(field + " = \"" + printable(name, 80) + "\": the asset requires " +
                 printable(name, 80) +
                 ", which pgt does not implement (of the extensions, pgt reads "
                 "KHR_mesh_quantization)");
    }
}

// What tinygltf would accept but pgt cannot read or use safely, checked on pgt's bounded JSON
// reader first: nesting deeper than 64 (tinygltf's parser recurses without a bound), a version
// other than 2, a required extension pgt lacks, a buffer uri that is absolute or holds a NUL,
// more than 2^24 triangles; and the estimate's buffers and primitive.
void precheck(const std::string& json, const std::string& path, const GltfSelection& which,
              MeshFrames frames, const Fail& fail, LoadEstimate& est, FsGuard& guard) {
    Json doc;
    try {
        doc = parseJsonText(json, path);
    } catch (const InputError& e) {
        fail("not a readable glTF 2.0 file: " + printable(e.what(), 300));
    }
    checkRequired(doc, fail);
    checkBuffers(doc, fail, est, guard);
    checkPrimitive(doc, which, frames, fail, est);
}

// The file's bytes, read after its JSON has been checked and the load estimated: a .gltf's
// JSON is the whole file (twice its size is refused before it is read: the bytes and their
// parsed document); a .glb's first chunk is read alone, then the whole file.
std::string checkedBytes(const std::string& path, const GltfSelection& which, MeshFrames frames,
                         const Fail& fail, FsGuard& guard) {
    const std::uintmax_t size = assetSize(path, fail);
    LoadEstimate est;
    est.file = double(size);
    std::string bytes = readRange(path, 0, std::min<std::uintmax_t>(20, size), fail);
    const bool binary = bytes.rfind("glTF", 0) == 0;
    if (!binary) {
        checkMemory(2 * est.file, fail.sceneFile, fail.field, path,
                    "reading a glTF file of " + formatNumber(std::ceil(est.file / (1 << 20)), 15) +
                        " MB (its bytes and its parsed JSON)");
        bytes = readRange(path, 0, size, fail);
    }
    {
        const std::string chunk = binary ? glbJson(path, bytes, size, fail) : "";
        const std::string& text = binary ? chunk : bytes;
        est.json = jsonCost(text, &est.transient) + double(chunk.size());
        checkMemory(est.bytes(), fail.sceneFile, fail.field, path, est.what());
        precheck(text, path, which, frames, fail, est, guard);
    }
    checkMemory(est.bytes(), fail.sceneFile, fail.field, path, est.what());
    return binary ? readRange(path, 0, size, fail) : bytes;
}

}  // namespace

tinygltf::Model readGltfModel(const std::string& path, const GltfSelection& which,
                              MeshFrames frames, const GltfFail& fail, std::string* sha1) {
    FsGuard guard{fs::absolute(path).parent_path().lexically_normal(), {}, 0};
    const std::string bytes = checkedBytes(path, which, frames, fail, guard);
    *sha1 = textSha1(bytes);
    const bool binary = bytes.rfind("glTF", 0) == 0;
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
