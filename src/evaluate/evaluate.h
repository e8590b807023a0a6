// Methods over fragments: the maps each method reads for one (s, b) (cached per study), the
// evaluation over all cores (C++ kernels, or a GLSL method in OpenGL), and the timing of a
// method alone, single-threaded.
#pragma once

#include <cmath>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "core/image.h"
#include "core/samples.h"
#include "heightfield/cone_map.h"
#include "heightfield/heightfield.h"
#include "heightfield/minmax_pyramid.h"
#include "methods/config.h"
#include "methods/method.h"
#include "raster/fragment_list.h"
#include "scene/scene.h"

namespace pgt {

struct VertexOutputs;  // methods/shader/vertex_stage.h

class GlMapUploads;  // methods/shader/glsl_method.h

// The maps (methods/maps.h) methods read at one (s, b): the height map, and the others the
// methods of a run need, owned (Lengyel FGED 2's derived maps, per (s, b)) or shared (the
// precomputed ones, per height map and sign of s).
struct MethodTextures {
    const Texture* height = nullptr;
    std::unique_ptr<DerivedMaps> derived;          // normal and parallax, when read
    std::shared_ptr<const MinMaxPyramid> pyramid;  // maxmip's, shared by every (s, b)
    std::shared_ptr<const ConeMap> cone;           // cone's, for the sign of s
    std::shared_ptr<const ConeMap> relaxedCone;    // relaxed_cone's, the same
    // By kind, null where not built (inline: a method context is made per fragment).
    MapRefs refs() const {
        MapRefs r;
        r.height = height;
        if (derived) r.normal = &derived->normal, r.parallax = &derived->parallax;
        r.pyramid = pyramid.get();
        r.cone = cone.get();
        r.relaxedCone = relaxedCone.get();
        return r;
    }
    double scale = 0, bias = 0;
    UvExtent uvExtent;  // the base's UV range (discard_outside)
    // GLSL methods: these maps' GL textures, uploaded on first use (under the GL lock),
    // deleted with this object.
    std::shared_ptr<GlMapUploads> glMaps;
};
MethodTextures makeMethodTextures(const Texture& height, double scale, double bias,
                                  const UvExtent& uvExtent, bool needDerived);

// The texture context a method runs with on `tex`: its maps and (s, b), rounded to the
// method's precision once, as a shader uniform would be. The one place a context is built.
template <class Real>
MethodContext<Real> makeMethodContext(const MethodTextures& tex) {
    MethodContext<Real> c;
    static_cast<MapRefs&>(c) = tex.refs();
    c.scale = Real(tex.scale);
    c.bias = Real(tex.bias);
    return c;
}

// Method textures by (s, b), built on first use: the truth's (s, b) and any method's own.
// A method whose "format" stores the map in fewer bits reads a rounded copy of it
// (heightfield/mipmaps.h storedMap), with maps of its own made from that copy.
class MethodTextureCache {
  public:
    MethodTextureCache(const Texture& height, const UvExtent& uvExtent,
                       StorageFormat own = StorageFormat::Float)
        : height_(height), uvExtent_(uvExtent), own_(own) {}
    // The maps `cfg` reads in a view of (s, b) `view`: its own (s, b) where it has one.
    // Builds the entry on first use (not thread-safe then; a hit only reads).
    const MethodTextures& get(const MethodConfig& cfg, const Displacement& view);
    // An entry that get() built already (thread-safe).
    const MethodTextures& at(const MethodConfig& cfg, const Displacement& view) const;
    // Drops every entry (a study moving to the next (s, b): its derived maps are W x H x 16
    // bytes each, so keeping every (s, b) would grow with the study).
    void clear();
    // The time its maps took to build a configuration's precomputed data in a view of (s, b)
    // `view` (ms; 0 if none): maxmip's pyramid, cone's map for the sign of s, and for
    // relaxed_cone that map plus the relaxed one built from it; each is built once for the map
    // and kept across clear().
    double precomputeMs(const MethodConfig& cfg, const Displacement& view) const;

  private:
    // The cache of the map as `format` stores it (its rounded copy made on first use).
    MethodTextureCache& stored(StorageFormat format);
    const MethodTextureCache& storedAt(StorageFormat format) const;
    struct Stored {
        Texture map;
        std::unique_ptr<MethodTextureCache> cache;
    };

    const Texture& height_;
    UvExtent uvExtent_;
    StorageFormat own_;
    std::map<StorageFormat, std::unique_ptr<Stored>> stored_;
    std::map<std::pair<double, double>, MethodTextures> cache_;
    std::shared_ptr<const MinMaxPyramid> pyramid_;
    double pyramidMs_ = 0;
    std::shared_ptr<const ConeMap> cone_[2], relaxed_[2];  // s >= 0, s < 0
    double coneMs_[2] = {0, 0}, relaxedMs_[2] = {0, 0};
};

// Memory of the maps `configs` read beyond the height map itself, estimated before any is
// built (bytes): each kind's MapKindInfo::bytesPerTexel (measured at 2048^2, with a build's
// peak; docs/performance.md), derived maps once per (s, b) they run at and x 4/3 with
// mipmaps, a relaxed cone map with the cone map it is made from, and for GLSL methods the
// GL's copies (4 bytes a channel; a software GL keeps them in this process).
double estimateMapBytes(const Texture& height, const std::vector<MethodConfig>& configs);

// Runs one method over all fragments (all cores); pixels not in the list stay uncovered.
// `exactFrame` feeds V in the exact frame instead of the per-vertex (Listing 7.4/7.8) frame.
Image2D<MethodPixel> evaluateMethod(const MethodConfig& cfg, const FragmentList& frags,
                                    const MethodTextures& tex, int width, int height,
                                    bool exactFrame = false);
// The same into `out`, reusing its storage when it has the size (a frame's bands); a shader
// with an engine vertex stage gets its outputs from `vertex` (methods/shader/vertex_stage.h;
// `frags` then has the triangles and barycentrics).
void evaluateMethod(const MethodConfig& cfg, const FragmentList& frags, const MethodTextures& tex,
                    int width, int height, bool exactFrame, Image2D<MethodPixel>& out,
                    const VertexOutputs* vertex = nullptr);

// What differs between a built-in and a shader for running them (the rest is
// methods/config.h's, runsInGl among it): a shader runs in OpenGL, over the fragments in
// screen layout (methods/shader/glsl_method.h GlslInputs: `frags`' pixels are y * width + x of
// the frame), one GL draw at a time; a built-in in C++ on all cores.
// Compiles a shader's program now (a study compiles every configuration before its first
// case, so that a compile error costs no case); nothing for a built-in.
void compileMethod(const MethodConfig& cfg);

struct TimingSpec {
    int repeats = 3;       // C++: median of this many single-threaded passes; GL: at least
    int maxFragments = 0;  // time a seeded subset of this many fragments (0 = all)
    uint32_t seed = 1;
    // GL: the subset repeated to at least this many fragments per draw, and draws until at
    // least glMinMs of GL time (methods/shader/glsl_method.h GlslTimingPlan).
    // NaN: kGlMinMsHardware on a hardware GL, kGlMinMsSoftware on a software one, whose
    // wall clock is not a GPU time and need not cost a GPU's budget.
    int64_t glFragments = 1 << 20;
    double glMinMs = NAN;
    // A study times a GLSL method once per (configuration, view direction) and shares it
    // across the view's (s, b) (docs/studies.md); false: every case (as `pgt render` does).
    bool glPerView = true;
};
constexpr double kGlMinMsHardware = 20, kGlMinMsSoftware = 5;

// Measured cost of the method alone in ns per fragment: the median and quartiles of its
// passes over `frags` (C++: `repeats` single-threaded passes; GL: the timing workload of
// `spec`), how many passes and how many fragments each pass evaluated.
struct MethodTiming {
    double median = NAN, p25 = NAN, p75 = NAN;  // NaN: not measured
    int repeats = 0;
    int64_t fragments = 0;
};
// A method with an engine vertex stage is timed with `vertex`, its outputs (the fragments'
// triangles and barycentrics read them); not timed (NaN) without them.
MethodTiming timeMethod(const MethodConfig& cfg, const FragmentList& frags,
                        const MethodTextures& tex, const TimingSpec& spec,
                        const VertexOutputs* vertex = nullptr);

// Where a method's ns/px comes from: "cpu" (single thread) or "gl: <GL_RENDERER>".
std::string timingBackend(const MethodConfig& cfg);

// The GL that ran this process's GLSL/HLSL methods (its vendor, renderer and version), none
// when none ran: an output's provenance records the GL only when it was used.
struct GlUsed {
    std::string vendor, renderer, version;
};
std::optional<GlUsed> glUsed();
// Picks the GL device GLSL/HLSL methods will run on, before the first of them does (the CLI's
// --gl-device: "" the EGL surfaceless platform, "egl-device:N" the N-th EGL device).
void selectGlDevice(const std::string& device);

}  // namespace pgt
