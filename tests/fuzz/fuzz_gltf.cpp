// libFuzzer target: the glTF reader on arbitrary bytes written as an asset (the first byte
// picks .gltf or .glb and the frames). Bad assets must end in InputError, never a crash; a
// loaded one has finite vertices, unit frames and indices below its vertex count.
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>

#include "core/error.h"
#include "mesh/gltf_mesh.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 1) return 0;
    // A folder of its own: a uri in the asset names files beside it, which are not there.
    const std::filesystem::path dir = "/tmp/pgt_fuzz_gltf_" + std::to_string(getpid());
    std::filesystem::create_directories(dir);
    const std::string path = (dir / ((data[0] & 1) ? "asset.glb" : "asset.gltf")).string();
    FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) return 0;
    std::fwrite(data + 1, 1, size - 1, f);
    std::fclose(f);
    const pgt::MeshFrames frames = (data[0] & 6) == 2   ? pgt::MeshFrames::MikkTSpace
                                   : (data[0] & 6) == 4 ? pgt::MeshFrames::Pgt
                                                        : pgt::MeshFrames::Asset;
    try {
        const pgt::GltfMesh m = pgt::loadGltfMesh(path, {}, frames, "fuzz.json", "base.file");
        const auto& mesh = m.drawn.mesh;
        for (uint32_t i : mesh.indices)
            if (i >= mesh.vertices.size()) __builtin_trap();
        for (const auto& v : mesh.vertices)
            if (!pgt::allFinite(v.position) || !pgt::allFinite(v.normal) ||
                !pgt::allFinite(v.tangent) || std::fabs(glm::length(v.normal) - 1) > 1e-6)
                __builtin_trap();
    } catch (const pgt::InputError&) {
    }
    std::filesystem::remove_all(dir);
    return 0;
}
