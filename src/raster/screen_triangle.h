// The rasteriser's triangle set-up (raster.cpp): a mesh triangle clipped at a pinhole's near
// plane, and each screen triangle of the clipped polygon with its edge functions, coverage
// test and perspective-correct interpolation. Internal to raster/.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>

#include "mesh/base_mesh.h"
#include "scene/camera.h"

namespace pgt::raster_detail {

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

inline ClipVertex lerp(const ClipVertex& a, const ClipVertex& c, double s) {
    return {a.cam + (c.cam - a.cam) * s,   a.world + (c.world - a.world) * s,
            a.uv + (c.uv - a.uv) * s,      a.t + (c.t - a.t) * s,
            a.b + (c.b - a.b) * s,         a.n + (c.n - a.n) * s,
            a.w + (c.w - a.w) * s,         a.eyeTangent + (c.eyeTangent - a.eyeTangent) * s,
            a.bary + (c.bary - a.bary) * s};
}

// Top-left rule in a y-down raster, for edges oriented so that the interior is on the
// positive side: a top edge runs exactly horizontally toward +x, a left edge runs upward.
inline bool isTopLeft(Vec2d a, Vec2d b) {
    Vec2d e = b - a;
    return (e.y == 0 && e.x > 0) || e.y < 0;
}

// The eye vector at a vertex in its Listing 7.8 frame, unnormalised (a per-vertex V).
inline Vec3d vertexEyeVector(const BaseVertex& p, const Camera& camera) {
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
inline ClippedPolygon clipToNear(const std::array<const BaseVertex*, 3>& v, const Camera& camera,
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

  private:
    // Screen weights divided by w, normalised.
    std::array<double, 3> weights(const std::array<double, 3>& e) const {
        double b0 = e[0] / area * invW[0], b1 = e[1] / area * invW[1], b2 = e[2] / area * invW[2];
        double sum = b0 + b1 + b2;
        return {b0 / sum, b1 / sum, b2 / sum};
    }
};

}  // namespace pgt::raster_detail
