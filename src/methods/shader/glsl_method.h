// GLSL methods: a user's shader function `vec2 F(vec2 uv, vec3 viewTangent)` run
// in a real OpenGL (EGL, headless: Mesa llvmpipe on machines without a GPU) over the
// rasteriser's fragments, with the same float uv0 and tangent-space V the C++ methods get.
// The only module that includes OpenGL/EGL headers.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "core/engine_inputs.h"
#include "core/math.h"
#include "heightfield/cone_map.h"
#include "heightfield/minmax_pyramid.h"
#include "heightfield/texture.h"
#include "methods/maps.h"
#include "methods/shader/glsl_spec.h"

namespace pgt {

// The GL the methods run in, named as the driver names itself.
struct GlInfo {
    std::string renderer, version, vendor;
    int glslVersion = 0;    // GL_SHADING_LANGUAGE_VERSION as a #version number (4.50 -> 450)
    bool software = false;  // llvmpipe / softpipe / swrast: timings are CPU timings
};

// The process's headless GL context (created on first use). `device` = "" picks the EGL
// surfaceless platform (Mesa: llvmpipe without a GPU); "egl-device:N" picks the N-th EGL
// device (a hardware GPU when one is present). Throws std::runtime_error when no GL 4.3+
// context can be made, with what was tried.
const GlInfo& glContext(const std::string& device = "");
// The context's renderer when GLSL methods made one in this process, none otherwise
// (provenance: an output records the GL only when GL ran).
std::optional<GlInfo> glContextIfMade();
// Selects the device before the first use (CLI --gl-device).
void setGlDevice(const std::string& device);

// The GL textures of one owner's maps, uploaded on first use and deleted with this object.
// A study keeps one per (s, b) beside its method textures (evaluate/evaluate.h), so each map
// is uploaded once per (s, b) and no texture outlives its map. Keyed by the map's address: the
// owner keeps its maps alive and unchanged while it holds this.
class GlMapUploads {
  public:
    GlMapUploads() = default;
    ~GlMapUploads();
    GlMapUploads(const GlMapUploads&) = delete;
    GlMapUploads& operator=(const GlMapUploads&) = delete;
    // The texture of `map` (as depth d = 1 - h when `depth`; a height map's value in the
    // channels of `channels`, GlslSpec::channels); uploads it on first use. Called by
    // runGlsl, under the GL lock.
    unsigned texture(const Texture& map, bool depth, unsigned channels = 0);
    // The height map packed as engines ship it (GlslSpec::Layout "normal+height" or
    // "normal+depth"): RGBA32F, RGB = 0.5 + 0.5 m from `normal`, A = h (1 - h when `depth`).
    unsigned packed(const Texture& height, const Texture& normal, bool depth);
    // The pyramid as one RG32F texture, level k from row levelRow(k) on (nearest texels).
    unsigned pyramid(const MinMaxPyramid& p);
    // A cone map (conservative or relaxed) as an R32F texture of its ratios (nearest texels).
    unsigned cone(const ConeMap& m);
    size_t size() const { return ids_.size(); }
    // Map textures alive in the process, over every owner.
    static size_t liveTextures();

  private:
    std::map<std::tuple<const Texture*, bool, unsigned>, unsigned> ids_;
    std::map<const void*, unsigned> precomputed_;  // pyramids and cone maps
    std::map<std::tuple<const Texture*, const Texture*, bool>, unsigned> packed_;
};

// The GL's time for a draw, per fragment: `nsPerPixel` and its quartiles are of the GL's
// clock (GL_TIME_ELAPSED on a hardware GL; the wall clock between two glFinish on a
// software one, whose timer queries do not cover its deferred rasterisation); both clocks'
// medians beside; the draws timed and the fragments each drew.
struct GlslTiming {
    double nsPerPixel = 0, p25 = 0, p75 = 0;
    double gpuNsPerPixel = 0, wallNsPerPixel = 0;
    int repeats = 0;
    int64_t fragments = 0;
};

// One run of a GLSL method over a list of fragments.
struct GlslRun {
    std::vector<Vec2f> uv;          // uv' per fragment
    std::vector<uint32_t> fetches;  // texture() calls per fragment
    GlslTiming timing;              // when timed
};

// What a draw samples: the maps (methods/maps.h; the height map always, the others where
// the spec names their samplers), uploaded through `uploads` when given, else for the call
// only; the case's (s, b) for uniforms bound to them, and the method's level of detail.
struct GlslMaps : MapRefs {
    double scale = 0, bias = 0;
    GlMapUploads* uploads = nullptr;
    bool lodGrad = false;  // pgt_sample: textureGrad with uv0's derivatives, else level 0
};

// The fragments of a draw. Packed (frameWidth 0): fragment k at texel (k % w, k / w), so
// a shader's own dFdx/dFdy see unrelated fragments. Screen layout (frameWidth > 0): each
// fragment at its pixel (y * frameWidth + x, y downward), drawn in tiles that keep the 2x2
// quads. With triangles and helpers (a frame's, RasterOptions::quadHelpers) each triangle's
// fragments of a quad get a quad of their own, as a GPU shades them: the first triangle's
// in place, any other's in rows below the tile, the lanes that are not the triangle's
// fragments its helper lanes (raster/raster.h HelperLane). dFdx, dFdy and implicit-LOD
// texture() then see each triangle's own plane, across triangle edges and UV seams too. A
// lane no helper fills (lists made by hand) is extended from a fragment of its quad along
// the derivatives (exact along the quad's row and column, which fine derivatives read), its
// V that fragment's.
struct GlslInputs {
    std::vector<Vec2f> uv0;
    // An engine's varyings (GlslSpec::engineInputs; empty: none), a helper's position moved
    // along the fragment's position derivatives as its uv0 is, its other inputs the fragment's.
    std::vector<EngineInputs> engine;
    std::vector<Vec3f> view;
    std::vector<Vec2f> uvDx, uvDy;  // uv0's derivatives (pgt_uv_dx, pgt_uv_dy); empty = 0
    std::vector<int32_t> pixel;     // screen layout only
    int frameWidth = 0, frameHeight = 0;
    // Screen layout: each fragment's triangle (empty: one quad per pixel quad) and the helper
    // lanes of the quads (at: the lane's pixel; x or y may equal the frame's odd side).
    struct Helper {
        Vec2i at{0};
        uint32_t triangle = 0;
        Vec2f uv0{0}, uvDx{0}, uvDy{0};
        Vec3f view{0};
        EngineInputs engine;
    };
    std::vector<uint32_t> triangle;
    std::vector<Helper> helpers;
    // The engine's vertex stage's outputs (GlslSpec::VertexStage links; 0: none): fragment k's
    // link l at varyings[k * links + l], helper j's at helperVaryings[j * links + l].
    int links = 0;
    std::vector<glm::vec4> varyings, helperVaryings;
};

// Compiles and links the spec's shader (cached, as runGlsl does) without drawing: a study
// calls it for each GLSL/HLSL method before it writes anything, so that a shader that does
// not compile leaves no output behind. Throws InputError as runGlsl does.
void compileGlsl(const GlslSpec& spec);

// Compiles the spec's shader (cached per source, function and sampler) and runs it over the
// fragments. Compile and link errors throw InputError naming the user's file and line.
// `timingRepeats` > 0 also times the draw with GL timer queries (each repeat one draw of
// every fragment).
GlslRun runGlsl(const GlslSpec& spec, const GlslMaps& maps, const GlslInputs& in,
                int timingRepeats = 0);
// The same, packed, at level 0 without derivatives (tests and benchmarks).
GlslRun runGlsl(const GlslSpec& spec, const MapRefs& maps, double scale, double bias,
                const std::vector<Vec2f>& uv0, const std::vector<Vec3f>& view,
                int timingRepeats = 0, GlMapUploads* uploads = nullptr);

// A fixed timing workload: `in`'s fragments (packed) repeated until at least `minFragments`,
// one warm-up draw, then draws until at least `minGpuMs` of GL time and at least
// `minRepeats` draws. The median and spread are per fragment of the workload.
struct GlslTimingPlan {
    int64_t minFragments = 1 << 20;
    double minGpuMs = 20;
    int minRepeats = 5, maxRepeats = 1000;
};
GlslRun timeGlsl(const GlslSpec& spec, const GlslMaps& maps, const GlslInputs& in,
                 const GlslTimingPlan& plan);

}  // namespace pgt
