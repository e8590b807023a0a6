// The rasteriser as it was before it worked in bins (commit c0e440a's raster.cpp, one pass
// over the whole frame with one depth buffer), kept frozen as the oracle the binned
// rasteriser must equal pixel for pixel. Not used by pgt itself.
#include "raster_reference.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace pgt::reference {

namespace {

// A clipped vertex: camera-space position plus the attributes to interpolate.
struct ClipVertex {
    Vec3d cam;  // (right, up, forward)
    Vec3d world;
    Vec2d uv;
    Vec3d t, b, n;
    double w;
};

ClipVertex lerp(const ClipVertex& a, const ClipVertex& c, double s) {
    return {a.cam + (c.cam - a.cam) * s, a.world + (c.world - a.world) * s,
            a.uv + (c.uv - a.uv) * s,    a.t + (c.t - a.t) * s,
            a.b + (c.b - a.b) * s,       a.n + (c.n - a.n) * s,
            a.w + (c.w - a.w) * s};
}

// Top-left rule in a y-down raster, for edges oriented so that the interior is on the
// positive side: a top edge runs exactly horizontally toward +x, a left edge runs upward.
bool isTopLeft(Vec2d a, Vec2d b) {
    Vec2d e = b - a;
    return (e.y == 0 && e.x > 0) || e.y < 0;
}

// Edge function (b - a) x (p - a), evaluated from the lexicographically smaller endpoint so
// that edge(a, b, p) == -edge(b, a, p) bit for bit: a pixel centre on an edge shared by two
// triangles then gets opposite signs (or zero) from both, and the top-left rule decides.
double edgeFunction(Vec2d a, Vec2d b, Vec2d p) {
    bool swap = b.x < a.x || (b.x == a.x && b.y < a.y);
    if (swap) std::swap(a, b);
    double e = (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
    return swap ? -e : e;
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

// The triangle in camera space, clipped (Sutherland-Hodgman) against forward >= nearZ for
// a pinhole camera: 0, 3 or 4 vertices.
std::vector<ClipVertex> clipToNear(const std::array<const BaseVertex*, 3>& v, const Camera& camera,
                                   double nearZ) {
    std::vector<ClipVertex> poly;
    for (auto* p : v)
        poly.push_back({camera.toCamera(p->position), p->position, p->uv, p->tangent, p->bitangent,
                        p->normal, p->handedness});
    if (camera.isOrthographic()) return poly;
    std::vector<ClipVertex> out;
    for (size_t i = 0; i < poly.size(); ++i) {
        const ClipVertex& a = poly[i];
        const ClipVertex& c = poly[(i + 1) % poly.size()];
        bool ina = a.cam.z >= nearZ, inc = c.cam.z >= nearZ;
        if (ina) out.push_back(a);
        if (ina != inc) out.push_back(lerp(a, c, (nearZ - a.cam.z) / (c.cam.z - a.cam.z)));
    }
    return out;
}

// One screen-space triangle of a clipped polygon, oriented so that its edge functions are
// positive inside, with the pixel range its samples can fall in.
struct ScreenTriangle {
    std::array<const ClipVertex*, 3> c;
    std::array<Vec2d, 3> s;
    std::array<double, 3> invW;
    std::array<bool, 3> topLeft;  // edge i is opposite vertex i: s[(i+1)%3] -> s[(i+2)%3]
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
        for (int i = 0; i < 3; ++i) topLeft[i] = isTopLeft(s[(i + 1) % 3], s[(i + 2) % 3]);
        return true;
    }

    // Perspective-correct barycentrics of sample p, or false when p is outside (top-left
    // rule on the edges).
    bool covers(Vec2d p, std::array<double, 3>& bary) const {
        std::array<double, 3> e;
        for (int i = 0; i < 3; ++i) {
            e[i] = edgeFunction(s[(i + 1) % 3], s[(i + 2) % 3], p);
            if (e[i] < 0 || (e[i] == 0 && !topLeft[i])) return false;
        }
        // Screen weights divided by w.
        double b0 = e[0] / area * invW[0], b1 = e[1] / area * invW[1], b2 = e[2] / area * invW[2];
        double sum = b0 + b1 + b2;
        bary = {b0 / sum, b1 / sum, b2 / sum};
        return true;
    }
};

// The fragment at barycentrics b: uv0, position and V in the per-vertex tangent frame
// (Lengyel FGED 2 Listing 7.8) and, when the triangle's UVs allow it, in the exact frame.
void shade(Fragment& f, const ScreenTriangle& tri, const std::array<double, 3>& b,
           const SurfaceDerivatives& d, const Camera& camera, double l) {
    const auto& c = tri.c;
    f.covered = true;
    f.uv0 = c[0]->uv * b[0] + c[1]->uv * b[1] + c[2]->uv * b[2];
    const Vec3d position = c[0]->world * b[0] + c[1]->world * b[1] + c[2]->world * b[2];
    // Lengyel FGED 2 Listing 7.8: n = normalize(normal); t = normalize(tangent - n * dot(tangent,
    // n)); b = cross(normal, tangent) * sigma.
    Vec3d n = glm::normalize(c[0]->n * b[0] + c[1]->n * b[1] + c[2]->n * b[2]);
    Vec3d t = c[0]->t * b[0] + c[1]->t * b[1] + c[2]->t * b[2];
    double w = c[0]->w * b[0] + c[1]->w * b[1] + c[2]->w * b[2];
    t = glm::normalize(t - n * glm::dot(n, t));
    Vec3d bt = glm::cross(n, t) * (w < 0 ? -1.0 : 1.0);
    Vec3d view = camera.viewVector(position);
    f.viewTangent = glm::normalize(Vec3d(glm::dot(t, view), glm::dot(bt, view), glm::dot(n, view)));
    f.viewTangentExact = f.viewTangent;
    f.exactFrame = d.exact;
    if (d.exact) {
        const Vec3d ve = uvSpaceDirection(d.dSdu, d.dSdv, n, l, view);
        f.exactFrame = ve != Vec3d(0);
        if (f.exactFrame) f.viewTangentExact = ve;
    }
}

// Every sample the triangle covers, nearest first (depth test on camera-space forward).
void scan(const ScreenTriangle& tri, const SurfaceDerivatives& d, const Camera& camera, double l,
          Image2D<Fragment>& frags, Image2D<double>& depth) {
    std::array<double, 3> b;
    for (int py = tri.py0; py <= tri.py1; ++py)
        for (int px = tri.px0; px <= tri.px1; ++px) {
            if (!tri.covers(camera.samplePosition(px, py), b)) continue;
            const auto& c = tri.c;
            double z = b[0] * c[0]->cam.z + b[1] * c[1]->cam.z + b[2] * c[2]->cam.z;
            if (!(z < depth.at(px, py))) continue;
            depth.at(px, py) = z;
            shade(frags.at(px, py), tri, b, d, camera, l);
        }
}

}  // namespace

Image2D<Fragment> rasterize(const BaseMesh& mesh, const Camera& camera,
                            const RasterOptions& options, RasterStats* stats) {
    Image2D<Fragment> frags(camera.width(), camera.height());
    Image2D<double> depth(camera.width(), camera.height(), std::numeric_limits<double>::infinity());
    RasterStats st;
    const bool ortho = camera.isOrthographic();
    const double nearZ = ortho ? 0 : nearPlane(mesh, camera);
    for (size_t tri = 0; tri + 2 < mesh.indices.size(); tri += 3) {
        std::array<const BaseVertex*, 3> v = {&mesh.vertices[mesh.indices[tri]],
                                              &mesh.vertices[mesh.indices[tri + 1]],
                                              &mesh.vertices[mesh.indices[tri + 2]]};
        // Facing: the geometric normal against the direction to the eye.
        Vec3d faceN = glm::cross(v[1]->position - v[0]->position, v[2]->position - v[0]->position);
        Vec3d toEye = ortho ? -camera.forward() : camera.eye() - v[0]->position;
        if (!(glm::dot(faceN, toEye) > 0) && options.cullBackFaces) {
            ++st.trianglesCulled;
            continue;
        }
        ++st.trianglesDrawn;
        const SurfaceDerivatives d = surfaceDerivatives(v);
        const std::vector<ClipVertex> poly = clipToNear(v, camera, nearZ);
        for (size_t k = 1; k + 1 < poly.size(); ++k) {
            ScreenTriangle screen;
            if (screen.setup(camera, {&poly[0], &poly[k], &poly[k + 1]}))
                scan(screen, d, camera, options.worldPerUv, frags, depth);
        }
    }
    for (const auto& f : frags.data) {
        st.covered += f.covered;
        st.noExactFrame += f.covered && !f.exactFrame;
    }
    if (stats) *stats = st;
    return frags;
}

}  // namespace pgt::reference
