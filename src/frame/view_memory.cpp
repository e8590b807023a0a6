// The memory a view needs (frame/view_memory.h).
#include "frame/view_memory.h"

#include <algorithm>

#include "core/error.h"
#include "core/memory.h"
#include "frame/frame_channels.h"
#include "frame/render.h"
#include "truth/builder.h"
#include "truth/tessellation.h"

namespace pgt {

double estimateViewBytes(const Scene& scene, int width, int height, const ViewMemory& m) {
    PGT_CHECK(m.configs);
    const double pixels = double(width) * height;
    // Twice with the exact-frame pass of a base whose vertex frames can differ from it.
    const double methods = double(m.configs->size()), mesh = framesCanDiffer(scene.base) ? 2 : 1;
    // A band: truth at two rates, the raster's fragments and their list (272 bytes at most:
    // every part and the FragmentInputs, raster/fragment_list.h), per
    // method its pixels and errors (twice on meshes, the exact-frame pass), and the EXR's
    // interleaved rows (frameChannelCount floats).
    const double band = double(width) * std::min(height, bandRows(width));
    double perBandPixel = 2.0 * sizeof(TruthSample) + 2.0 * sizeof(Fragment) + 272 +
                          methods * (sizeof(MethodPixel) + sizeof(float)) * mesh;
    // A GL draw's triangles and helper lanes: at most 3 lanes a fragment (one alone in its
    // quad), in the raster's list and the smaller copy the draw makes.
    if (rasterOptions(scene, scene.view(), m.mapConfigs ? *m.mapConfigs : *m.configs).quadHelpers)
        perBandPixel += 4 + 3.0 * 2 * sizeof(HelperLane);
    if (m.writesImages)
        perBandPixel +=
            double(frameChannelCount(m.configs->size(), readsFragmentInputs(*m.configs))) *
            sizeof(float) * 2;
    // The frame: each method's kept errors (float) for its percentiles, the truth's own, the
    // error maps' float images; or everything when the images are kept.
    double perPixel = (methods + 1) * sizeof(float);
    if (m.writesImages) perPixel += methods * sizeof(float);
    if (m.keepsImages)
        perPixel += sizeof(TruthSample) + sizeof(Fragment) +
                    methods * (sizeof(MethodPixel) + sizeof(float));
    double truth = 0;  // a plane's lattice (a mesh's truth is in its own estimate)
    if (scene.plane()) {
        // What the view's frame builds: the lattice over its window (frameWindow; the whole
        // tile where the view needs it), not the whole plane at every rate.
        truth = truthVertices(scene, makeCamera(scene), lightToward(scene.view())) *
                kTruthBytesPerGridVertex;
        if (m.truthInBlocks) {
            truth = std::min(truth, double(scene.truth.memoryMb) * 1024 * 1024);
            perPixel += 2.0 * sizeof(TruthSample);  // the blocks fill whole frames
        }
    }
    return band * perBandPixel + pixels * perPixel + truth +
           estimateMapBytes(scene.height, m.mapConfigs ? *m.mapConfigs : *m.configs);
}

void checkViewMemory(const Scene& scene, int width, int height, const ViewMemory& m,
                     const std::string& field) {
    checkMeshTruthMemory(scene);
    checkMemory(estimateViewBytes(scene, width, height, m), scene.file, field,
                std::to_string(width) + "x" + std::to_string(height),
                "a " + std::to_string(width) + "x" + std::to_string(height) + " frame with " +
                    std::to_string(m.configs->size()) + " method(s), their maps and its truth");
}

double bytesBesideTruth(const Scene& scene, const Camera& camera, bool writesImages,
                        bool keepsImages) {
    const ViewMemory view{
        .configs = &scene.methods, .writesImages = writesImages, .keepsImages = keepsImages};
    const double lattice =
        scene.plane() ? truthVertices(scene, makeCamera(scene), lightToward(scene.view())) : 0.0;
    return estimateViewBytes(scene, camera.width(), camera.height(), view) -
           lattice * kTruthBytesPerGridVertex +
           2.0 * sizeof(TruthSample) * camera.width() * camera.height();
}

}  // namespace pgt
