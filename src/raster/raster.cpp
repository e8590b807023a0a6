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

namespace pgt {

namespace {

// A clipped vertex: camera-space position plus the attributes to interpolate.
struct ClipVertex {
    Vec3d cam;  // (right, up, forward)
    Vec3d world;
    Vec2d uv;
    Vec3d t, b, n;
    double w;
    Vec3d eyeTangent;  // the vertex's eye vector in its own frame (FragmentInputs::viewVertex)
    Vec3d bary;        // its barycentrics in the mesh's triangle (FragmentInputs::bary)
};

ClipVertex lerp(const ClipVertex& a, const ClipVertex& c, double s) {
    return {a.cam + (c.cam - a.cam) * s,   a.world + (c.world - a.world) * s,
            a.uv + (c.uv - a.uv) * s,      a.t + (c.t - a.t) * s,
            a.b + (c.b - a.b) * s,         a.n + (c.n - a.n) * s,
            a.w + (c.w - a.w) * s,         a.eyeTangent + (c.eyeTangent - a.eyeTangent) * s,
            a.bary + (c.bary - a.bary) * s};
}

// Top-left rule in a y-down raster, for edges oriented so that the interior is on the
// positive side: a top edge runs exactly horizontally toward +x, a left edge runs upward.
bool isTopLeft(Vec2d a, Vec2d b) {
    Vec2d e = b - a;
    return (e.y == 0 && e.x > 0) || e.y < 0;
}

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

// The eye vector at a vertex in its Listing 7.8 frame, unnormalised (a per-vertex V).
Vec3d vertexEyeVector(const BaseVertex& p, const Camera& camera) {
    const Vec3d n = glm::normalize(p.normal);
    const Vec3d t = glm::normalize(p.tangent - n * glm::dot(n, p.tangent));
    const Vec3d b = glm::cross(n, t) * (p.handedness < 0 ? -1.0 : 1.0);
    const Vec3d e = camera.isOrthographic() ? -camera.forward() : camera.eye() - p.position;
    return {glm::dot(t, e), glm::dot(b, e), glm::dot(n, e)};
}

// A triangle clipped at the near plane: up to 4 vertices (one plane cuts off at most one
// corner's worth), kept in place, no allocation.
struct ClippedPolygon {
    std::array<ClipVertex, 4> v;
    int size = 0;
};

// The triangle in camera space, clipped (Sutherland-Hodgman) against forward >= nearZ for
// a pinhole camera: 0, 3 or 4 vertices; with each vertex's eye vector when `eyeVectors`
// (a per-vertex V is asked for).
ClippedPolygon clipToNear(const std::array<const BaseVertex*, 3>& v, const Camera& camera,
                          bool eyeVectors, double nearZ) {
    std::array<ClipVertex, 3> poly;
    for (int i = 0; i < 3; ++i) {
        const BaseVertex* p = v[size_t(i)];
        poly[size_t(i)] = {camera.toCamera(p->position),
                           p->position,
                           p->uv,
                           p->tangent,
                           p->bitangent,
                           p->normal,
                           p->handedness,
                           eyeVectors ? vertexEyeVector(*p, camera) : Vec3d(0),
                           Vec3d(i == 0, i == 1, i == 2)};
    }
    ClippedPolygon out;
    if (camera.isOrthographic()) {
        for (int i = 0; i < 3; ++i) out.v[size_t(i)] = poly[size_t(i)];
        out.size = 3;
        return out;
    }
    for (size_t i = 0; i < 3; ++i) {
        const ClipVertex& a = poly[i];
        const ClipVertex& c = poly[(i + 1) % 3];
        bool ina = a.cam.z >= nearZ, inc = c.cam.z >= nearZ;
        if (ina) out.v[size_t(out.size++)] = a;
        if (ina != inc)
            out.v[size_t(out.size++)] = lerp(a, c, (nearZ - a.cam.z) / (c.cam.z - a.cam.z));
    }
    return out;
}

// An edge function (b - a) x (p - a) set up once per edge, evaluated from the
// lexicographically smaller endpoint so that edge(a, b, p) == -edge(b, a, p) bit for bit: a
// pixel centre on an edge shared by two triangles then gets opposite signs (or zero) from
// both, and the top-left rule decides.
struct Edge {
    Vec2d a{0};
    double dx = 0, dy = 0;
    bool negate = false;
    Edge() = default;
    Edge(Vec2d from, Vec2d to)
        : a(from), negate(to.x < from.x || (to.x == from.x && to.y < from.y)) {
        if (negate) std::swap(a, to);
        dx = to.x - a.x, dy = to.y - a.y;
    }
    double at(Vec2d p) const {
        const double e = dx * (p.y - a.y) - dy * (p.x - a.x);
        return negate ? -e : e;
    }
};

// One screen-space triangle of a clipped polygon, oriented so that its edge functions are
// positive inside, with the pixel range its samples can fall in.
struct ScreenTriangle {
    std::array<const ClipVertex*, 3> c;
    std::array<Vec2d, 3> s;
    std::array<double, 3> invW;
    std::array<Edge, 3> edge;     // edge i is opposite vertex i: s[(i+1)%3] -> s[(i+2)%3]
    std::array<bool, 3> topLeft;  // of edge i
    double area = 0;
    int px0 = 0, px1 = -1, py0 = 0, py1 = -1;

    // False for a degenerate (zero or non-finite area) triangle.
    bool setup(const Camera& camera, std::array<const ClipVertex*, 3> verts) {
        c = verts;
        const bool ortho = camera.isOrthographic();
        for (int i = 0; i < 3; ++i) {
            s[i] = camera.toScreen(c[i]->cam);
            invW[i] = ortho ? 1.0 : 1.0 / c[i]->cam.z;
        }
        area = (s[1].x - s[0].x) * (s[2].y - s[0].y) - (s[1].y - s[0].y) * (s[2].x - s[0].x);
        if (area == 0 || !std::isfinite(area)) return false;
        if (area < 0) {
            std::swap(c[1], c[2]);
            std::swap(s[1], s[2]);
            std::swap(invW[1], invW[2]);
            area = -area;
        }
        double x0 = std::min({s[0].x, s[1].x, s[2].x}), x1 = std::max({s[0].x, s[1].x, s[2].x});
        double y0 = std::min({s[0].y, s[1].y, s[2].y}), y1 = std::max({s[0].y, s[1].y, s[2].y});
        // Every pixel whose sample position (centre or jittered, inside the pixel) can fall
        // in the bounding box (clamped in double first: a triangle clipped just in front of
        // a pinhole eye can project to beyond +-2^31 pixels, where an int conversion is
        // undefined).
        auto index = [](double x, int lo, int hi) { return x <= lo ? lo : x >= hi ? hi : int(x); };
        const int W = camera.width(), H = camera.height();
        px0 = index(std::floor(x0) - 1, 0, W - 1), px1 = index(std::ceil(x1), 0, W - 1);
        py0 = index(std::floor(y0) - 1, 0, H - 1), py1 = index(std::ceil(y1), 0, H - 1);
        for (int i = 0; i < 3; ++i) {
            edge[i] = Edge(s[(i + 1) % 3], s[(i + 2) % 3]);
            topLeft[i] = isTopLeft(s[(i + 1) % 3], s[(i + 2) % 3]);
        }
        return true;
    }

    // Whether sample p is inside (top-left rule on the edges), with its perspective-correct
    // barycentrics.
    bool covers(Vec2d p, std::array<double, 3>& bary) const {
        std::array<double, 3> e;
        for (int i = 0; i < 3; ++i) e[i] = edge[i].at(p);
        for (int i = 0; i < 3; ++i)
            if (e[i] < 0 || (e[i] == 0 && !topLeft[i])) return false;
        bary = weights(e);
        return true;
    }
    // The perspective-correct barycentrics of any screen point (a helper lane's).
    std::array<double, 3> barycentrics(Vec2d p) const {
        return weights({edge[0].at(p), edge[1].at(p), edge[2].at(p)});
    }

    // An attribute (uv, position) at any screen point, inside the triangle or not (a helper
    // invocation's): the perspective-correct interpolation with one division (the area
    // cancels); equal to the barycentrics' to rounding.
    template <class Attribute>
    Attribute at(Vec2d p, Attribute ClipVertex::*attribute) const {
        double k[3], sum = 0;
        for (int i = 0; i < 3; ++i) k[i] = edge[i].at(p) * invW[i], sum += k[i];
        return (c[0]->*attribute * k[0] + c[1]->*attribute * k[1] + c[2]->*attribute * k[2]) / sum;
    }
    Vec2d uv(const std::array<double, 3>& b) const {
        return c[0]->uv * b[0] + c[1]->uv * b[1] + c[2]->uv * b[2];
    }
    Vec3d position(const std::array<double, 3>& b) const {
        return c[0]->world * b[0] + c[1]->world * b[1] + c[2]->world * b[2];
    }

  private:
    // Screen weights divided by w, normalised.
    std::array<double, 3> weights(const std::array<double, 3>& e) const {
        double b0 = e[0] / area * invW[0], b1 = e[1] / area * invW[1], b2 = e[2] / area * invW[2];
        double sum = b0 + b1 + b2;
        return {b0 / sum, b1 / sum, b2 / sum};
    }
};

// uv0's fine quad derivatives at pixel (px, py) (Fragment::uvDx, uvDy): the differences
// across the pixel centres of the quad's pair along x and along y, one of which is the
// pixel's own centre. `centred`: the pixel is sampled at its centre, so uv0 is its uv there.
void quadDerivatives(Fragment& f, FragmentInputs* in, const ScreenTriangle& tri, int px, int py,
                     bool centred) {
    const bool left = (px & 1) == 0, top = (py & 1) == 0;  // the pixel's place in its quad
    const Vec2d own(px + 0.5, py + 0.5);
    const Vec2d xOther(own.x + (left ? 1 : -1), own.y), yOther(own.x, own.y + (top ? 1 : -1));
    const Vec2d uvOwn = centred ? f.uv0 : tri.at(own, &ClipVertex::uv);
    const Vec2d uvX = tri.at(xOther, &ClipVertex::uv), uvY = tri.at(yOther, &ClipVertex::uv);
    f.uvDx = left ? uvX - uvOwn : uvOwn - uvX;
    f.uvDy = top ? uvY - uvOwn : uvOwn - uvY;
    if (!in) return;  // an engine's position derivatives, where asked
    const Vec3f pOwn(tri.at(own, &ClipVertex::world));
    const Vec3f pX(tri.at(xOther, &ClipVertex::world)), pY(tri.at(yOther, &ClipVertex::world));
    in->engine.positionDx = left ? pX - pOwn : pOwn - pX;
    in->engine.positionDy = top ? pY - pOwn : pOwn - pY;
}

// The fragment at barycentrics b: uv0, position and V in the per-vertex tangent frame
// (Lengyel FGED 2 Listing 7.8) and, when the triangle's UVs allow it and the options ask,
// in the exact frame, per vertex and an engine's inputs.
void shade(Fragment& f, FragmentInputs* in, const ScreenTriangle& tri,
           const std::array<double, 3>& b, const SurfaceDerivatives& d, const Camera& camera,
           const Ray& ray, const RasterOptions& o) {
    const auto& c = tri.c;
    f.covered = true;
    f.uv0 = tri.uv(b);
    const Vec3d position = tri.position(b);
    // Lengyel FGED 2 Listing 7.8: n = normalize(normal); t = normalize(tangent - n * dot(tangent,
    // n)); b = cross(normal, tangent) * sigma.
    const Vec3d nRaw = c[0]->n * b[0] + c[1]->n * b[1] + c[2]->n * b[2];
    Vec3d n = glm::normalize(nRaw);
    Vec3d t = c[0]->t * b[0] + c[1]->t * b[1] + c[2]->t * b[2];
    double w = c[0]->w * b[0] + c[1]->w * b[1] + c[2]->w * b[2];
    if (in && o.engineInputs) {  // as interpolated (EngineInputs)
        in->engine.position = Vec3f(position);
        in->engine.normal = Vec3f(nRaw);
        in->engine.tangent = Vec3f(t);
        in->engine.tangentW = w < 0 ? -1.0f : 1.0f;
    }
    t = glm::normalize(t - n * glm::dot(n, t));
    Vec3d bt = glm::cross(n, t) * (w < 0 ? -1.0 : 1.0);
    Vec3d view = camera.viewVector(position);
    f.viewTangent = glm::normalize(Vec3d(glm::dot(t, view), glm::dot(bt, view), glm::dot(n, view)));
    f.viewTangentExact = f.viewTangent;
    if (in) {
        in->bary = c[0]->bary * b[0] + c[1]->bary * b[1] + c[2]->bary * b[2];
        in->viewVertex = f.viewTangent;
        if (o.perVertexView)
            in->viewVertex = glm::normalize(c[0]->eyeTangent * b[0] + c[1]->eyeTangent * b[1] +
                                            c[2]->eyeTangent * b[2]);
    }
    f.rayT = glm::dot(position - ray.origin, ray.dir);
    // The eye; orthographic rays start on a plane through the target, so their origin moves
    // back to one world unit beyond the drawn point (EngineInputs::camera).
    if (in && o.engineInputs)
        in->engine.camera =
            Vec3f(camera.isOrthographic() ? ray.origin - ray.dir * (std::fabs(f.rayT) + 1.0)
                                          : ray.origin);
    const Vec3d light = o.light;  // a unit vector, zero where the view has none
    auto toFrame = [&](Vec3d x, Vec3d y, Vec3d z) {
        return light == Vec3d(0) ? Vec3d(0)
                                 : glm::normalize(Vec3d(glm::dot(x, light), glm::dot(y, light),
                                                        glm::dot(z, light)));
    };
    f.lightTangent = f.lightTangentExact = toFrame(t, bt, n);
    f.exactFrame = d.exact;
    if (d.exact && o.exactFrame) {
        const Vec3d ve = uvSpaceDirection(d.dSdu, d.dSdv, n, o.worldPerUv, view);
        f.exactFrame = ve != Vec3d(0);
        if (f.exactFrame) {
            f.viewTangentExact = ve;
            if (light != Vec3d(0))
                f.lightTangentExact = uvSpaceDirection(d.dSdu, d.dSdv, n, o.worldPerUv, light);
        }
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
            Fragment& f = frags.at(ox, oy);
            FragmentInputs* in = inputs ? &inputs->at(ox, oy) : nullptr;
            shade(f, in, tri, b, d, camera, camera.ray(sample.x, sample.y), o);
            quadDerivatives(f, in && o.engineInputs ? in : nullptr, tri, px, py,
                            !camera.jittered());
            f.triangle = triangle;
        }
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
    // (shade, quadDerivatives and the triangle): the image is not cleared beforehand.
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
    for (Vec2i lane : lanes) {
        HelperLane& h = out.emplace_back();
        h.at = lane + shift;
        h.fragment.triangle = t;
        if (!any) continue;
        const Vec2d sample = ownerSample + Vec2d(lane - owner);
        shade(h.fragment, &h.inputs, screen, screen.barycentrics(sample), d, camera_,
              camera_.ray(sample.x, sample.y), options_);
        quadDerivatives(h.fragment, options_.engineInputs ? &h.inputs : nullptr, screen, lane.x,
                        lane.y, !camera_.jittered());
        h.fragment.triangle = t;
    }
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
