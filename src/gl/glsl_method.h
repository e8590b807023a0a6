// GLSL methods: a user's shader function `vec2 F(vec2 uv, vec3 viewTangent)` run
// in a real OpenGL (EGL, headless: Mesa llvmpipe on machines without a GPU) over the
// rasteriser's fragments, with the same float uv0 and tangent-space V the C++ methods get.
// The only module that includes OpenGL/EGL headers.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/math.h"
#include "heightfield/cone_map.h"
#include "heightfield/minmax_pyramid.h"
#include "heightfield/texture.h"
#include "methods/glsl_spec.h"

namespace pgt {

// The GL the methods run in, named as the driver names itself.
struct GlInfo {
    std::string renderer, version, vendor;
    bool software = false;  // llvmpipe / softpipe / swrast: timings are CPU timings
};

// The process's headless GL context (created on first use). `device` = "" picks the EGL
// surfaceless platform (Mesa: llvmpipe without a GPU); "egl-device:N" picks the N-th EGL
// device (a hardware GPU when one is present). Throws std::runtime_error when no GL 4.3+
// context can be made, with what was tried.
const GlInfo& glContext(const std::string& device = "");
// Selects the device before the first use (CLI --gl-device).
void setGlDevice(const std::string& device);

// The GL textures of one owner's maps, uploaded on first use and deleted with this object.
// A study keeps one per (s, b) beside its method textures (study/evaluate.h), so each map is
// uploaded once per (s, b) and no texture outlives its map. Keyed by the map's address: the
// owner keeps its maps alive and unchanged while it holds this.
class GlMapUploads {
  public:
    GlMapUploads() = default;
    ~GlMapUploads();
    GlMapUploads(const GlMapUploads&) = delete;
    GlMapUploads& operator=(const GlMapUploads&) = delete;
    // The texture of `map` (as depth d = 1 - h when `depth`); uploads it on first use.
    // Called by runGlsl, under the GL lock.
    unsigned texture(const Texture& map, bool depth);
    // The pyramid as one RG32F texture, level k from row levelRow(k) on (nearest texels).
    unsigned pyramid(const MinMaxPyramid& p);
    // A cone map (conservative or relaxed) as an R32F texture of its ratios (nearest texels).
    unsigned cone(const ConeMap& m);
    size_t size() const { return ids_.size(); }
    // Map textures alive in the process, over every owner.
    static size_t liveTextures();

  private:
    std::map<std::pair<const Texture*, bool>, unsigned> ids_;
    std::map<const void*, unsigned> precomputed_;  // pyramids and cone maps
};

// One run of a GLSL method over a list of fragments.
struct GlslRun {
    std::vector<Vec2f> uv;          // uv' per fragment
    std::vector<uint32_t> fetches;  // texture() calls per fragment
    double gpuNsPerPixel = 0;       // GL_TIME_ELAPSED of the draw, median of the repeats
    double wallNsPerPixel = 0;      // the same draw between two glFinish, wall clock
};

// Compiles the spec's shader (cached per source, function and sampler) and runs it over the
// fragments. The maps are uploaded through `uploads` (kept by the caller with its maps), or,
// without one, for this call only. Compile and link errors throw InputError naming the user's file
// and line. `timingRepeats` > 0 also times the draw with GL timer queries. `normal` and `parallax`
// are 003's derived maps (needed when the spec names their samplers). `scale`, `bias`: the (s, b)
// of the case, for uniforms bound to them. `pyramid`, `cone`: the height map's (needed when
// the spec names a pyramid or cone sampler).
GlslRun runGlsl(const GlslSpec& spec, const Texture& height, const Texture* normal,
                const Texture* parallax, double scale, double bias, const std::vector<Vec2f>& uv0,
                const std::vector<Vec3f>& view, int timingRepeats = 0,
                GlMapUploads* uploads = nullptr, const MinMaxPyramid* pyramid = nullptr,
                const ConeMap* cone = nullptr, const ConeMap* relaxedCone = nullptr);

}  // namespace pgt
