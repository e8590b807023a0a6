// CPU rasteriser of the base mesh (docs/model.md §6): what the GPU's parallax-mapped draw sees.
// Pixel centres, the top-left fill rule, a depth test, near-plane clipping, and
// perspective-correct interpolation of UV, position and the tangent frame. Per covered
// pixel it gives uv0 and the tangent-space view vector V.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/engine_inputs.h"
#include "core/image.h"
#include "core/math.h"
#include "mesh/base_mesh.h"
#include "scene/camera.h"

namespace pgt {

struct Fragment {
    bool covered = false;
    // False where the triangle's UVs are degenerate (then viewTangentExact repeats
    // viewTangent).
    bool exactFrame = false;
    Vec2d uv0{0};
    Vec3d viewTangent{0};  // unit V in tangent space (V.T, V.B, V.N); methods round to float
    // V in the exact frame of the drawn surface (docs/model.md §2): the true UV-space
    // direction of the ray, (a, b, c) normalised with V = a dS/du + b dS/dv + c l N for the
    // drawn triangle's dS/du, dS/dv and the interpolated normal N the truth displaces along
    // (uvSpaceDirection). A method marching along it follows the ray exactly over an affine
    // patch, shear and unequal scales included. Equal to viewTangent on a plane.
    Vec3d viewTangentExact{0};
    // uv0's screen derivatives as a GPU's fine dFdx/dFdy give them: differences of this
    // triangle's perspective-correct uv (extended beyond its edges, as for a helper
    // invocation) between the two pixel centres of the 2x2 quad's row (x) and column (y).
    // Quads start at even x and y; y grows downward (image rows). Non-finite where the
    // neighbour's centre is beyond a pinhole's horizon.
    // Made only with RasterOptions::uvDerivatives (zero otherwise).
    Vec2d uvDx{0}, uvDy{0};
    // The direction toward the view's light in the per-vertex and the exact frame (zero
    // without a light, docs/model.md §6c), and the distance along the pixel's ray to the drawn
    // point (world units; the base of the depth offsets, §5b).
    Vec3d lightTangent{0}, lightTangentExact{0};
    double rayT = NAN;
    uint32_t triangle = 0;  // the base mesh face that drew it (its first index / 3)
};

// What some methods read besides a Fragment, made only when one of the frame's methods does
// (RasterOptions::perVertexView, engineInputs) into an image of its own beside the fragments.
struct FragmentInputs {
    // V computed per vertex and interpolated, as jMonkeyEngine's and Ogre's vertex shaders
    // do: at each vertex the eye vector (eye - position; orthographic: minus the view
    // direction) in that vertex's Listing 7.8 frame, unnormalised, interpolated perspective-
    // correctly, then normalised (methods' "V": "per_vertex"). Equal to viewTangent on a
    // flat triangle with one frame.
    Vec3d viewVertex{0};
    EngineInputs engine;
    // The drawn point's barycentrics in its mesh triangle (Fragment::triangle's vertices in
    // index order): perspective-correct, so any per-vertex value (an engine's vertex stage's
    // outputs) interpolates as a GPU's varyings do. Made with RasterOptions::barycentrics.
    Vec3d bary{0};
};

struct RasterOptions {
    bool cullBackFaces = true;
    double worldPerUv = 1;  // l (docs/model.md §2): the height axis of the exact frame
    // What the frame's methods read beyond uv0 and V, each computed per pixel only when asked
    // (frame/render.h rasterOptions; uv0's derivatives: uvDerivatives below): V in the exact frame
    // (off: viewTangentExact repeats viewTangent), V per vertex and an engine's inputs (into the
    // FragmentInputs image a caller passes; off: not made).
    bool exactFrame = true, perVertexView = true, engineInputs = true;
    // The helper lanes of the frame's 2x2 quads (HelperLane), for a GL draw that lays the
    // fragments out on the screen (a GLSL or HLSL method).
    bool quadHelpers = false;
    // FragmentInputs::bary (an engine's vertex stage: methods/shader/vertex_stage.h).
    bool barycentrics = false;
    // uv0's quad derivatives (Fragment::uvDx, uvDy; off: zero), read by a method with
    // "lod": "grad" and by every GL draw.
    bool uvDerivatives = true;
    // The unit world direction toward the view's light (scene.h lightToward), zero without
    // one: each fragment's lightTangent and lightTangentExact.
    Vec3d light{0};
};

// A helper invocation of a 2x2 quad, as a GPU runs one (docs/model.md §6): where a quad holds
// fragments of a triangle and lanes that are not that triangle's (uncovered, another
// triangle's, or beyond the frame's odd edge), each such lane is the triangle's fragment
// evaluated there, barycentrics extended beyond its edges. Its sample is the lane's pixel
// centre, moved as the quad's first fragment of the triangle is by jitter. A GL draw gives
// each triangle's fragments a quad of their own from these, so that dFdx, dFdy and implicit
// levels of detail see the triangle's own plane and never a neighbouring triangle.
struct HelperLane {
    Vec2i at{0};  // the lane's pixel in the rasterised image (x may be its width when odd)
    Fragment fragment;
    FragmentInputs inputs;
};

// The UV-space direction of world direction `dir` at a point whose surface derivatives are
// dSdu, dSdv and whose unit normal is n, l world units to one UV unit of height: (a, b, c)
// normalised, with dir = a dSdu + b dSdv + c l n (docs/model.md §2, the exact frame). Zero
// where dSdu, dSdv and n are (near) coplanar or `dir` is zero.
Vec3d uvSpaceDirection(const Vec3d& dSdu, const Vec3d& dSdv, const Vec3d& n, double l,
                       const Vec3d& dir);

struct RasterStats {
    int64_t covered = 0;
    int64_t noExactFrame = 0;  // covered pixels on triangles with degenerate UVs
    int64_t trianglesDrawn = 0;
    int64_t trianglesCulled = 0;
};

// The base mesh prepared once for a camera: faces culled, and the indices of the rest
// binned into kBin x kBin pixel bins by their clipped screen bounds. A triangle's screen
// set-up is redone in every bin it touches, which costs less than keeping it for a
// million-face mesh. Any pixel rectangle is then rasterised on its own, on any thread and
// in any order, equal pixel for pixel to the whole frame drawn at once: inside a rectangle
// the triangles that can reach it are drawn in mesh order with the same depth test.
// `mesh` and `camera` must outlive it.
class Rasterizer {
  public:
    static constexpr int kBin = 32;
    Rasterizer(const BaseMesh& mesh, const Camera& camera, const RasterOptions& options);

    // The fragments of `rect` into `out`, resized to the rectangle (pixel (x, y) at
    // out.at(x - rect.x0, y - rect.y0)); adds its covered pixels to `stats`. No allocation
    // once `out` has the size.
    void rasterize(PixelRect rect, Image2D<Fragment>& out, RasterStats& stats) const;
    // Rows [y0, y1) of the frame into `out` (resized to W x (y1 - y0)), bin by bin over all
    // cores; adds their covered pixels to `stats`.
    // With `inputs`, also their FragmentInputs (resized like `out`) where the options ask.
    // With `helpers` and RasterOptions::quadHelpers, also the quads' helper lanes, pixels
    // relative to `out` (else `helpers` is left empty).
    void rasterizeRows(int y0, int y1, Image2D<Fragment>& out, RasterStats& stats,
                       Image2D<FragmentInputs>* inputs = nullptr,
                       std::vector<HelperLane>* helpers = nullptr) const;
    // Triangles drawn and culled.
    const RasterStats& setupStats() const { return setup_; }
    const RasterOptions& options() const { return options_; }

  private:
    // rasterize() into `out` at `at` (rect's top-left pixel there): every pixel of rect written,
    // a drawn one whole, the others cleared; `inputs` (when given) the caller cleared.
    void rasterizeAt(PixelRect rect, Image2D<Fragment>& out, Image2D<FragmentInputs>* inputs,
                     Vec2i at, RasterStats& stats) const;
    // The helper lanes of rect's quads (rect's corner even), drawn into `out` at `at`.
    void quadHelpers(PixelRect rect, const Image2D<Fragment>& out, Vec2i at,
                     std::vector<HelperLane>& helpers) const;
    // Triangle t's `lanes` of the quad whose first fragment of t is at `owner`, set up once,
    // appended to `out` at lane + `shift`.
    void helperLanes(uint32_t t, Vec2i owner, std::span<const Vec2i> lanes, Vec2i shift,
                     std::vector<HelperLane>& out) const;
    const BaseMesh& mesh_;
    const Camera& camera_;
    RasterOptions options_;
    double nearZ_ = 0;
    int binsX_ = 0, binsY_ = 0;
    // Bin b's triangles (first index of each) in mesh order: binTriangles_[binStart_[b] ..
    // binStart_[b + 1]).
    std::vector<uint64_t> binStart_;
    std::vector<uint32_t> binTriangles_;
    RasterStats setup_;
};

// The whole frame at once (all cores).
Image2D<Fragment> rasterize(const BaseMesh& mesh, const Camera& camera,
                            const RasterOptions& options, RasterStats* stats = nullptr,
                            Image2D<FragmentInputs>* inputs = nullptr,
                            std::vector<HelperLane>* helpers = nullptr);

}  // namespace pgt
