// Scanline-free half-space rasteriser (edge functions at pixel centres, top-left rule) with
// perspective-correct attribute interpolation, in double precision.
#include "raster/raster.h"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <span>
#include <vector>

#include "core/error.h"
#include "raster/lanes.h"
#include "raster/screen_triangle.h"

namespace pgt {

namespace {

using namespace raster_detail;

// Pinhole near plane: a thousandth of the eye's distance to the nearest vertex keeps
// clipped triangles well conditioned while losing nothing visible in practice.
double nearPlane(const BaseMesh& mesh, const Camera& camera) {
    double nearest = std::numeric_limits<double>::infinity();
    for (const auto& v : mesh.vertices)
        nearest = std::min(nearest, glm::length(v.position - camera.eye()));
    return std::max(1e-9, nearest * 1e-3);
}

// The drawn triangle's exact dS/du and dS/dv (Lengyel FGED 2 Eq. 7.37 without averaging); false
// when its UVs are degenerate.
struct SurfaceDerivatives {
    Vec3d dSdu{0}, dSdv{0};
    bool exact = false;
};
SurfaceDerivatives surfaceDerivatives(const std::array<const BaseVertex*, 3>& v) {
    SurfaceDerivatives d;
    Vec3d e1 = v[1]->position - v[0]->position, e2 = v[2]->position - v[0]->position;
    Vec2d d1 = v[1]->uv - v[0]->uv, d2 = v[2]->uv - v[0]->uv;
    double det = d1.x * d2.y - d2.x * d1.y;
    // Degenerate UVs: |det| below 1e-12 of the squared UV edge lengths (as mesh/refine.cpp).
    double scale = std::max(glm::dot(d1, d1), glm::dot(d2, d2));
    if (std::fabs(det) > 1e-12 * scale && std::isfinite(det)) {
        d.dSdu = (e1 * d2.y - e2 * d1.y) / det;
        d.dSdv = (e2 * d1.x - e1 * d2.x) / det;
        d.exact = true;
    }
    return d;
}

// An engine's position derivatives at pixel (px, py) (EngineInputs::positionDx, positionDy):
// across the pixel centres of the quad's pair along x and along y, as uv0's (quadUvDerivatives).
void positionDerivatives(FragmentInputs& in, const ScreenTriangle& tri, int px, int py) {
    const bool left = (px & 1) == 0, top = (py & 1) == 0;  // the pixel's place in its quad
    const Vec2d own(px + 0.5, py + 0.5);
    const Vec2d xOther(own.x + (left ? 1 : -1), own.y), yOther(own.x, own.y + (top ? 1 : -1));
    const Vec3f pOwn(tri.at(own, &ClipVertex::world));
    const Vec3f pX(tri.at(xOther, &ClipVertex::world)), pY(tri.at(yOther, &ClipVertex::world));
    in.engine.positionDx = left ? pX - pOwn : pOwn - pX;
    in.engine.positionDy = top ? pY - pOwn : pOwn - pY;
}

// The lanes' uv at screen points (x, y), by ScreenTriangle::at's arithmetic.
void uvAt(const ScreenTriangle& tri, const Lanes& x, const Lanes& y, Lanes& u, Lanes& v) {
    std::array<Lanes, 3> k;
    for (size_t i = 0; i < 3; ++i)
        for (size_t l = 0; l < kLanes; ++l) k[i][l] = tri.edge[i].at({x[l], y[l]}) * tri.invW[i];
    const auto& c = tri.c;
    for (size_t l = 0; l < kLanes; ++l) {
        const double sum = ((0.0 + k[0][l]) + k[1][l]) + k[2][l];
        u[l] = (c[0]->uv.x * k[0][l] + c[1]->uv.x * k[1][l] + c[2]->uv.x * k[2][l]) / sum;
        v[l] = (c[0]->uv.y * k[0][l] + c[1]->uv.y * k[1][l] + c[2]->uv.y * k[2][l]) / sum;
    }
}

// uv0's fine quad derivatives at the lanes' pixels (Fragment::uvDx, uvDy): the differences
// across the pixel centres of each quad's pair along x and along y, one of which is the
// pixel's own centre. `centred`: pixels are sampled at their centres, so uv0 (u0, v0) is the
// uv there.
void quadUvDerivatives(const ScreenTriangle& tri, const std::array<Vec2i, kLanes>& pixel,
                       bool centred, const Lanes& u0, const Lanes& v0, Lanes3& dx, Lanes3& dy) {
    Lanes ownX, ownY, xX, yY, uOwn = u0, vOwn = v0, uX, vX, uY, vY;
    for (size_t l = 0; l < kLanes; ++l) {
        ownX[l] = pixel[l].x + 0.5, ownY[l] = pixel[l].y + 0.5;
        xX[l] = ownX[l] + ((pixel[l].x & 1) == 0 ? 1 : -1);
        yY[l] = ownY[l] + ((pixel[l].y & 1) == 0 ? 1 : -1);
    }
    if (!centred) uvAt(tri, ownX, ownY, uOwn, vOwn);
    uvAt(tri, xX, ownY, uX, vX);
    uvAt(tri, ownX, yY, uY, vY);
    for (size_t l = 0; l < kLanes; ++l) {
        const bool left = (pixel[l].x & 1) == 0, top = (pixel[l].y & 1) == 0;
        dx.x[l] = left ? uX[l] - uOwn[l] : uOwn[l] - uX[l];
        dx.y[l] = left ? vX[l] - vOwn[l] : vOwn[l] - vX[l];
        dy.x[l] = top ? uY[l] - uOwn[l] : uOwn[l] - uY[l];
        dy.y[l] = top ? vY[l] - vOwn[l] : vOwn[l] - vY[l];
    }
}

// A fragment's light in the per-vertex frame (t, bt, n) and, with V, both in the exact frame
// when the triangle's UVs allow it and the options ask (the rest of shadeLanes).
void lightAndExactFrame(Fragment& f, const Vec3d& t, const Vec3d& bt, const Vec3d& n,
                        const Vec3d& view, const SurfaceDerivatives& d, const RasterOptions& o) {
    const Vec3d light = o.light;  // a unit vector, zero where the view has none
    f.lightTangent = f.lightTangentExact =
        light == Vec3d(0)
            ? Vec3d(0)
            : glm::normalize(Vec3d(glm::dot(t, light), glm::dot(bt, light), glm::dot(n, light)));
    f.exactFrame = d.exact;
    if (!d.exact || !o.exactFrame) return;
    const Vec3d ve = uvSpaceDirection(d.dSdu, d.dSdv, n, o.worldPerUv, view);
    f.exactFrame = ve != Vec3d(0);
    if (!f.exactFrame) return;
    f.viewTangentExact = ve;
    if (light != Vec3d(0))
        f.lightTangentExact = uvSpaceDirection(d.dSdu, d.dSdv, n, o.worldPerUv, light);
}

// The FragmentInputs of fragment f at barycentrics b besides an engine's interpolated
// attributes (shadeLanes): the mesh barycentrics, the per-vertex V and an engine's camera.
void fillInputs(FragmentInputs& in, const Fragment& f, const ScreenTriangle& tri,
                const std::array<double, 3>& b, const Ray& ray, const Camera& camera,
                const RasterOptions& o) {
    const auto& c = tri.c;
    in.bary = c[0]->bary * b[0] + c[1]->bary * b[1] + c[2]->bary * b[2];
    in.viewVertex = f.viewTangent;
    if (o.perVertexView)
        in.viewVertex = glm::normalize(c[0]->eyeTangent * b[0] + c[1]->eyeTangent * b[1] +
                                       c[2]->eyeTangent * b[2]);
    // The eye; orthographic rays start on a plane through the target, so their origin moves
    // back to one world unit beyond the drawn point (EngineInputs::camera).
    if (o.engineInputs)
        in.engine.camera =
            Vec3f(camera.isOrthographic() ? ray.origin - ray.dir * (std::fabs(f.rayT) + 1.0)
                                          : ray.origin);
}

// A pixel to shade: its fragment (and inputs, when made), barycentrics in the screen triangle,
// sample position and pixel.
struct LanePixel {
    Fragment* f = nullptr;
    FragmentInputs* in = nullptr;
    std::array<double, 3> b{};
    Vec2d sample{0};
    Vec2i pixel{0};
};

// Camera::viewVector at the lanes' world positions.
Lanes3 viewLanes(const Camera& camera, const Lanes3& position) {
    Lanes3 view;
    if (camera.isOrthographic()) {  // one direction, not normalised again
        const Vec3d back = -camera.forward();
        view.x.fill(back.x), view.y.fill(back.y), view.z.fill(back.z);
        return view;
    }
    const Vec3d eye = camera.eye();
    for (size_t l = 0; l < kLanes; ++l)
        view.x[l] = eye.x - position.x[l], view.y[l] = eye.y - position.y[l],
        view.z[l] = eye.z - position.z[l];
    normalize(view);
    return view;
}

// The fragments of up to kLanes pixels of one screen triangle, each step over all of them
// before the next (their square roots and divisions pack into vector registers and overlap),
// with the bits one pixel at a time would give: uv0, position and V in the per-vertex tangent
// frame (Lengyel FGED 2 Listing 7.8) and, when the options ask, uv0's quad derivatives, V per
// vertex, an engine's inputs and (where the triangle's UVs allow it) V in the exact frame.
void shadeLanes(std::span<const LanePixel> p, const ScreenTriangle& tri,
                const SurfaceDerivatives& d, const Camera& camera, const RasterOptions& o) {
    const auto& c = tri.c;
    const size_t count = p.size();
    PGT_CHECK(count > 0 && count <= kLanes);
    // Lanes past `count` repeat the first pixel and are not written (their rays not made).
    std::array<Lanes, 3> b;
    std::array<Vec2i, kLanes> pixel;
    std::array<Ray, kLanes> ray;
    for (size_t l = 0; l < kLanes; ++l) {
        const LanePixel& q = p[l < count ? l : 0];
        for (size_t i = 0; i < 3; ++i) b[i][l] = q.b[i];
        pixel[l] = q.pixel;
        if (l < count) ray[l] = camera.ray(q.sample.x, q.sample.y);
    }
    const Lanes u = interpolate(c[0]->uv.x, c[1]->uv.x, c[2]->uv.x, b);
    const Lanes v = interpolate(c[0]->uv.y, c[1]->uv.y, c[2]->uv.y, b);
    const Lanes3 position = interpolate(c[0]->world, c[1]->world, c[2]->world, b);
    const Lanes3 nRaw = interpolate(c[0]->n, c[1]->n, c[2]->n, b);
    Lanes3 t = interpolate(c[0]->t, c[1]->t, c[2]->t, b);
    const Lanes w = interpolate(c[0]->w, c[1]->w, c[2]->w, b);
    for (size_t l = 0; l < count; ++l)
        if (p[l].in && o.engineInputs) {  // as interpolated (EngineInputs)
            EngineInputs& e = p[l].in->engine;
            e.position = Vec3f(position.at(l));
            e.normal = Vec3f(nRaw.at(l));
            e.tangent = Vec3f(t.at(l));
            e.tangentW = w[l] < 0 ? -1.0f : 1.0f;
        }
    // Lengyel FGED 2 Listing 7.8: n = normalize(normal); t = normalize(tangent - n * dot(tangent,
    // n)); b = cross(normal, tangent) * sigma.
    Lanes3 n = nRaw;
    normalize(n);
    const Lanes nt = dot(n, t);
    Lanes sign;
    for (size_t l = 0; l < kLanes; ++l) {
        t.x[l] -= n.x[l] * nt[l], t.y[l] -= n.y[l] * nt[l], t.z[l] -= n.z[l] * nt[l];
        sign[l] = w[l] < 0 ? -1.0 : 1.0;
    }
    normalize(t);
    const Lanes3 bt = cross(n, t, sign);
    const Lanes3 view = viewLanes(camera, position);
    Lanes3 viewTangent{dot(t, view), dot(bt, view), dot(n, view)};
    normalize(viewTangent);
    Lanes3 uvDx{}, uvDy{};
    if (o.uvDerivatives) quadUvDerivatives(tri, pixel, !camera.jittered(), u, v, uvDx, uvDy);
    for (size_t l = 0; l < count; ++l) {
        Fragment& f = *p[l].f;
        FragmentInputs* in = p[l].in;
        f.covered = true;
        f.uv0 = Vec2d(u[l], v[l]);
        f.viewTangent = f.viewTangentExact = viewTangent.at(l);
        f.uvDx = Vec2d(uvDx.x[l], uvDx.y[l]), f.uvDy = Vec2d(uvDy.x[l], uvDy.y[l]);
        const Vec3d at = position.at(l);
        f.rayT = glm::dot(at - ray[l].origin, ray[l].dir);
        if (in) fillInputs(*in, f, tri, p[l].b, ray[l], camera, o);
        if (in && o.engineInputs) positionDerivatives(*in, tri, pixel[l].x, pixel[l].y);
        lightAndExactFrame(f, t.at(l), bt.at(l), n.at(l), view.at(l), d, o);
    }
}

}  // namespace

Vec3d uvSpaceDirection(const Vec3d& dSdu, const Vec3d& dSdv, const Vec3d& n, double l,
                       const Vec3d& dir) {
    // Cramer's rule for dir = a dSdu + b dSdv + c (l n).
    const Vec3d ln = n * l;
    const double det = glm::dot(dSdu, glm::cross(dSdv, ln));
    const double size = glm::length(dSdu) * glm::length(dSdv) * l;
    if (!(std::fabs(det) > 1e-9 * size) || !std::isfinite(det)) return Vec3d(0);
    const Vec3d abc(glm::dot(dir, glm::cross(dSdv, ln)), glm::dot(dSdu, glm::cross(dir, ln)),
                    glm::dot(dSdu, glm::cross(dSdv, dir)));
    const double len = glm::length(abc);  // of det times the direction
    return len > 0 && std::isfinite(len) ? abc / (det > 0 ? len : -len) : Vec3d(0);
}

namespace {

// Every sample of `rect` the triangle covers, nearest first (depth test on camera-space
// forward); `frags` and `depth` are the rectangle's.
void scan(const ScreenTriangle& tri, uint32_t triangle, const SurfaceDerivatives& d,
          const Camera& camera, const RasterOptions& o, PixelRect rect, Image2D<Fragment>& frags,
          Image2D<FragmentInputs>* inputs, Vec2i at, Image2D<double>& depth) {
    std::array<LanePixel, kLanes> lanes;
    size_t pending = 0;
    auto flush = [&] {
        shadeLanes({lanes.data(), pending}, tri, d, camera, o);
        for (size_t l = 0; l < pending; ++l) lanes[l].f->triangle = triangle;
        pending = 0;
    };
    std::array<double, 3> b;
    const int y0 = std::max(tri.py0, rect.y0), y1 = std::min(tri.py1, rect.y1 - 1);
    const int x0 = std::max(tri.px0, rect.x0), x1 = std::min(tri.px1, rect.x1 - 1);
    for (int py = y0; py <= y1; ++py)
        for (int px = x0; px <= x1; ++px) {
            const Vec2d sample = camera.samplePosition(px, py);
            if (!tri.covers(sample, b)) continue;
            const auto& c = tri.c;
            double z = b[0] * c[0]->cam.z + b[1] * c[1]->cam.z + b[2] * c[2]->cam.z;
            double& nearest = depth.at(px - rect.x0, py - rect.y0);
            if (!(z < nearest)) continue;
            nearest = z;
            const int ox = px - rect.x0 + at.x, oy = py - rect.y0 + at.y;
            lanes[pending++] = {&frags.at(ox, oy), inputs ? &inputs->at(ox, oy) : nullptr, b,
                                sample, Vec2i(px, py)};
            if (pending == kLanes) flush();
        }
    if (pending > 0) flush();
}

std::array<const BaseVertex*, 3> triangleVertices(const BaseMesh& mesh, size_t first) {
    return {&mesh.vertices[mesh.indices[first]], &mesh.vertices[mesh.indices[first + 1]],
            &mesh.vertices[mesh.indices[first + 2]]};
}

// Facing: the geometric normal against the direction to the eye.
bool facesCamera(const std::array<const BaseVertex*, 3>& v, const Camera& camera) {
    Vec3d faceN = glm::cross(v[1]->position - v[0]->position, v[2]->position - v[0]->position);
    Vec3d toEye = camera.isOrthographic() ? -camera.forward() : camera.eye() - v[0]->position;
    return glm::dot(faceN, toEye) > 0;
}

// The bins a drawn triangle's clipped screen triangles can reach (empty: none).
struct BinRange {
    int x0 = 0, x1 = -1, y0 = 0, y1 = -1;
};

BinRange binRange(const std::array<const BaseVertex*, 3>& v, const Camera& camera, double nearZ) {
    const ClippedPolygon poly = clipToNear(v, camera, false, nearZ);
    BinRange r;
    bool any = false;
    for (int k = 1; k + 1 < poly.size; ++k) {
        ScreenTriangle screen;
        if (!screen.setup(camera, {&poly.v[0], &poly.v[size_t(k)], &poly.v[size_t(k + 1)]}))
            continue;
        const int B = Rasterizer::kBin;
        BinRange t{screen.px0 / B, screen.px1 / B, screen.py0 / B, screen.py1 / B};
        r = any ? BinRange{std::min(r.x0, t.x0), std::max(r.x1, t.x1), std::min(r.y0, t.y0),
                           std::max(r.y1, t.y1)}
                : t;
        any = true;
    }
    return r;
}

}  // namespace

Rasterizer::Rasterizer(const BaseMesh& mesh, const Camera& camera, const RasterOptions& options)
    : mesh_(mesh), camera_(camera), options_(options) {
    nearZ_ = camera.isOrthographic() ? 0 : nearPlane(mesh, camera);
    binsX_ = (camera.width() + kBin - 1) / kBin;
    binsY_ = (camera.height() + kBin - 1) / kBin;
    const size_t triangles = mesh.indices.size() / 3;
    // Each triangle's bins (in parallel), then the bins' lists in mesh order (counting sort).
    std::vector<BinRange> ranges(triangles);
    std::vector<uint8_t> drawn(triangles, 0);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, triangles, 4096), [&](const auto& r) {
        for (size_t t = r.begin(); t < r.end(); ++t) {
            const auto v = triangleVertices(mesh, 3 * t);
            if (!facesCamera(v, camera) && options.cullBackFaces) continue;
            drawn[t] = 1;
            ranges[t] = binRange(v, camera, nearZ_);
        }
    });
    binStart_.assign(size_t(binsX_) * binsY_ + 1, 0);
    for (size_t t = 0; t < triangles; ++t) {
        drawn[t] ? ++setup_.trianglesDrawn : ++setup_.trianglesCulled;
        for (int by = ranges[t].y0; by <= ranges[t].y1; ++by)
            for (int bx = ranges[t].x0; bx <= ranges[t].x1; ++bx)
                ++binStart_[size_t(by) * binsX_ + bx + 1];
    }
    for (size_t b = 1; b < binStart_.size(); ++b) binStart_[b] += binStart_[b - 1];
    binTriangles_.resize(binStart_.back());
    std::vector<uint64_t> fill(binStart_.begin(), binStart_.end() - 1);
    for (size_t t = 0; t < triangles; ++t)
        for (int by = ranges[t].y0; by <= ranges[t].y1; ++by)
            for (int bx = ranges[t].x0; bx <= ranges[t].x1; ++bx)
                binTriangles_[fill[size_t(by) * binsX_ + bx]++] = uint32_t(t);
}

void Rasterizer::rasterize(PixelRect rect, Image2D<Fragment>& out, RasterStats& stats) const {
    PGT_CHECK(rect.x0 >= 0 && rect.y0 >= 0 && rect.x1 <= camera_.width() &&
              rect.y1 <= camera_.height() && !rect.empty());
    sizeImage(out, rect.width(), rect.height());  // rasterizeAt writes every pixel
    rasterizeAt(rect, out, nullptr, {0, 0}, stats);
}

void Rasterizer::rasterizeAt(PixelRect rect, Image2D<Fragment>& out,
                             Image2D<FragmentInputs>* inputs, Vec2i at, RasterStats& stats) const {
    thread_local Image2D<double> depth;
    thread_local std::vector<uint32_t> triangles;
    if (depth.width != rect.width() || depth.height != rect.height())
        depth = Image2D<double>(rect.width(), rect.height());
    std::fill(depth.data.begin(), depth.data.end(), std::numeric_limits<double>::infinity());
    // The triangles of every bin the rectangle touches, in mesh order, each once.
    triangles.clear();
    const int bx0 = rect.x0 / kBin, bx1 = (rect.x1 - 1) / kBin;
    const int by0 = rect.y0 / kBin, by1 = (rect.y1 - 1) / kBin;
    for (int by = by0; by <= by1; ++by)
        for (int bx = bx0; bx <= bx1; ++bx) {
            const size_t b = size_t(by) * binsX_ + bx;
            triangles.insert(triangles.end(), binTriangles_.begin() + int64_t(binStart_[b]),
                             binTriangles_.begin() + int64_t(binStart_[b + 1]));
        }
    if (bx1 > bx0 || by1 > by0) {
        std::sort(triangles.begin(), triangles.end());
        triangles.erase(std::unique(triangles.begin(), triangles.end()), triangles.end());
    }
    for (uint32_t t : triangles) {
        const auto v = triangleVertices(mesh_, 3 * size_t(t));
        const SurfaceDerivatives d = surfaceDerivatives(v);
        const ClippedPolygon poly = clipToNear(v, camera_, options_.perVertexView, nearZ_);
        for (int k = 1; k + 1 < poly.size; ++k) {
            ScreenTriangle screen;
            if (screen.setup(camera_, {&poly.v[0], &poly.v[size_t(k)], &poly.v[size_t(k + 1)]}))
                scan(screen, t, d, camera_, options_, rect, out, inputs, at, depth);
        }
    }
    // A pixel no triangle drew is cleared here, the drawn ones having been written whole
    // (shadeLanes and the triangle): the image is not cleared beforehand.
    for (int y = 0; y < rect.height(); ++y)
        for (int x = 0; x < rect.width(); ++x) {
            Fragment& f = out.at(x + at.x, y + at.y);
            if (depth.at(x, y) == std::numeric_limits<double>::infinity()) {
                f = Fragment{};
                continue;
            }
            stats.covered += f.covered;
            stats.noExactFrame += f.covered && !f.exactFrame;
        }
}

void Rasterizer::rasterizeRows(int y0, int y1, Image2D<Fragment>& out, RasterStats& stats,
                               Image2D<FragmentInputs>* inputs,
                               std::vector<HelperLane>* helpers) const {
    const int W = camera_.width();
    // Each bin of columns writes every one of its pixels in place (rasterizeAt).
    sizeImage(out, W, y1 - y0);
    const bool wantInputs =
        inputs && (options_.perVertexView || options_.engineInputs || options_.barycentrics);
    if (wantInputs) resetImage(*inputs, W, y1 - y0);
    const int bins = (W + kBin - 1) / kBin;
    const bool wantHelpers = helpers && options_.quadHelpers;
    std::vector<std::vector<HelperLane>> binHelpers(wantHelpers ? size_t(bins) : 0);
    tbb::combinable<RasterStats> counts;
    tbb::parallel_for(0, bins, [&](int b) {
        const PixelRect rect{b * kBin, y0, std::min(W, (b + 1) * kBin), y1};
        rasterizeAt(rect, out, wantInputs ? inputs : nullptr, {rect.x0, 0}, counts.local());
        if (wantHelpers) quadHelpers(rect, out, {rect.x0, 0}, binHelpers[size_t(b)]);
    });
    counts.combine_each([&](const RasterStats& c) {
        stats.covered += c.covered;
        stats.noExactFrame += c.noExactFrame;
    });
    if (!helpers) return;
    helpers->clear();
    for (const auto& h : binHelpers) helpers->insert(helpers->end(), h.begin(), h.end());
}

void Rasterizer::quadHelpers(PixelRect rect, const Image2D<Fragment>& out, Vec2i at,
                             std::vector<HelperLane>& helpers) const {
    PGT_CHECK(rect.x0 % 2 == 0 && rect.y0 % 2 == 0);
    for (int qy = rect.y0; qy < rect.y1; qy += 2)
        for (int qx = rect.x0; qx < rect.x1; qx += 2) {
            // The quad's lanes in GL's order: (x, y), (x + 1, y), (x, y + 1), (x + 1, y + 1).
            std::array<const Fragment*, 4> lane{};
            for (int i = 0; i < 4; ++i) {
                const int x = qx + (i & 1), y = qy + (i >> 1);
                if (x >= rect.x1 || y >= rect.y1) continue;
                const Fragment& f = out.at(x - rect.x0 + at.x, y - rect.y0 + at.y);
                if (f.covered) lane[size_t(i)] = &f;
            }
            for (int i = 0; i < 4; ++i) {
                if (!lane[size_t(i)]) continue;
                const uint32_t t = lane[size_t(i)]->triangle;
                bool first = true;  // the quad's first fragment of t owns its helpers
                for (int j = 0; j < i; ++j)
                    first = first && !(lane[size_t(j)] && lane[size_t(j)]->triangle == t);
                if (!first) continue;
                std::array<Vec2i, 3> others;
                int n = 0;
                for (int j = 0; j < 4; ++j)
                    if (!(lane[size_t(j)] && lane[size_t(j)]->triangle == t))
                        others[size_t(n++)] = Vec2i(qx + (j & 1), qy + (j >> 1));
                helperLanes(t, Vec2i(qx + (i & 1), qy + (i >> 1)), {others.data(), size_t(n)},
                            at - Vec2i(rect.x0, rect.y0), helpers);
            }
        }
}

void Rasterizer::helperLanes(uint32_t t, Vec2i owner, std::span<const Vec2i> lanes, Vec2i shift,
                             std::vector<HelperLane>& out) const {
    const auto v = triangleVertices(mesh_, 3 * size_t(t));
    const ClippedPolygon poly = clipToNear(v, camera_, options_.perVertexView, nearZ_);
    // Any piece of the clipped polygon: they share the triangle's plane.
    ScreenTriangle screen;
    int k = 1;
    while (k + 1 < poly.size &&
           !screen.setup(camera_, {&poly.v[0], &poly.v[size_t(k)], &poly.v[size_t(k + 1)]}))
        ++k;
    const bool any = k + 1 < poly.size;
    const SurfaceDerivatives d = surfaceDerivatives(v);
    const Vec2d ownerSample = camera_.samplePosition(owner.x, owner.y);
    const size_t first = out.size();
    std::array<LanePixel, kLanes> pixels;
    for (Vec2i lane : lanes) {
        HelperLane& h = out.emplace_back();
        h.at = lane + shift;
        h.fragment.triangle = t;
    }
    if (!any || lanes.empty()) return;
    for (size_t i = 0; i < lanes.size(); ++i) {  // 3 lanes at most: one call
        HelperLane& h = out[first + i];
        const Vec2d sample = ownerSample + Vec2d(lanes[i] - owner);
        pixels[i] = {&h.fragment, &h.inputs, screen.barycentrics(sample), sample, lanes[i]};
    }
    shadeLanes({pixels.data(), lanes.size()}, screen, d, camera_, options_);
}

Image2D<Fragment> rasterize(const BaseMesh& mesh, const Camera& camera,
                            const RasterOptions& options, RasterStats* stats,
                            Image2D<FragmentInputs>* inputs, std::vector<HelperLane>* helpers) {
    const Rasterizer raster(mesh, camera, options);
    Image2D<Fragment> frags;
    RasterStats st = raster.setupStats();
    raster.rasterizeRows(0, camera.height(), frags, st, inputs, helpers);
    if (stats) *stats = st;
    return frags;
}

}  // namespace pgt
