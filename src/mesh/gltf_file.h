// Reading a glTF 2.0 file into tinygltf's model (mesh/gltf_mesh.cpp's first step): the file
// bounded, its JSON read first by pgt's bounded reader, the memory the whole load will take
// estimated from the file's size and its JSON before any buffer is read, buffers confined to
// the asset's folder, images left undecoded. Internal to mesh/.
#pragma once

#include <tiny_gltf.h>

#include <string>

#include "core/error.h"
#include "mesh/gltf_mesh.h"

namespace pgt {

// Errors about a glTF asset: the scene's file and field, the asset's path, what is wrong.
struct GltfFail {
    const std::string& sceneFile;
    const std::string& field;  // the asset's field (base.file)
    const std::string& path;
    [[noreturn]] void operator()(const std::string& what) const {
        throw InputError(sceneFile, field, path, what);
    }
    // A selection the scene made (base.mesh, base.primitive, ...): named by its own field.
    [[noreturn]] void at(const std::string& key, const std::string& what) const {
        const size_t dot = field.rfind('.');
        throw InputError(sceneFile,
                         (dot == std::string::npos ? "" : field.substr(0, dot + 1)) + key, path,
                         what);
    }
};

// The drawn primitive has at most this many triangles.
constexpr size_t kMaxGltfTriangles = size_t(1) << 24;

// The file parsed by tinygltf after pgt's own checks, which include the selected primitive's
// triangle count and the memory estimate of reading the file and building `which` with
// `frames` (checkMemory); bad input throws through `fail`. `sha1` gets the SHA-1 of the
// file's bytes (read once).
tinygltf::Model readGltfModel(const std::string& path, const GltfSelection& which,
                              MeshFrames frames, const GltfFail& fail, std::string* sha1);

}  // namespace pgt
