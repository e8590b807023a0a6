// The memory a view needs, estimated before anything is allocated: its frame's bands, its
// kept images, its methods' maps and its truth (frame/render.h runs the view; this decides
// whether it may, and how a plane's truth is split into blocks to fit).
#pragma once

#include <string>
#include <vector>

#include "methods/method.h"
#include "scene/camera.h"
#include "scene/scene.h"

namespace pgt {

// Memory one view needs, estimated before anything is allocated (bytes): per band, the
// truth (two rates), the rasteriser's fragments and the methods' images; per pixel of the
// frame, each method's kept error (float) for the percentiles and, when `writesImages`, for
// its error map, or the whole frame's images when `keepsImages`; the maps the methods read
// (estimateMapBytes); plus the truth geometry (a plane's lattice at the scene's rate and 2x,
// capped by truth.memory_mb when the frame may be traced in blocks, which then keeps the whole
// frame's truth). Throws InputError naming `field` when it exceeds the memory limit
// (core/memory.h).
struct ViewMemory {
    const std::vector<MethodConfig>* configs = nullptr;  // the methods run at once
    // The methods whose maps are held and whose fragments the views are rasterised for (pgt fit
    // runs one method at a time over all); null: configs.
    const std::vector<MethodConfig>* mapConfigs = nullptr;
    bool writesImages = false;  // frame.exr and the error maps
    bool keepsImages = false;   // the whole frame's images in memory (FrameOptions)
    bool truthInBlocks = false;
};
double estimateViewBytes(const Scene& scene, int width, int height, const ViewMemory& m);
void checkViewMemory(const Scene& scene, int width, int height, const ViewMemory& m,
                     const std::string& field);

// Memory of a view beside its plane truth's lattice: its frame, its methods' maps, and the
// whole frames that truth blocks fill (what a block's lattice must leave room for).
double bytesBesideTruth(const Scene& scene, const Camera& camera, bool writesImages,
                        bool keepsImages);

}  // namespace pgt
