// How far Embree's single precision can be trusted: sampled float hits re-intersected in
// double with the same triangle and the unrounded ray (TruthSurface::checkPrecision).
#include <cmath>
#include <random>
#include <vector>

#include "compare/statistics.h"
#include "truth/embree_sheet.h"
#include "truth/truth.h"

namespace pgt {

namespace {
// Moller-Trumbore in double: t and the barycentrics (b1 on p1, b2 on p2) where the ray meets
// the triangle's plane; inside when b1, b2 >= 0 and b1 + b2 <= 1 (within `slack`).
bool intersectDouble(Vec3d o, Vec3d d, Vec3d p0, Vec3d p1, Vec3d p2, double slack, double& t,
                     double& b1, double& b2) {
    Vec3d e1 = p1 - p0, e2 = p2 - p0, pv = glm::cross(d, e2);
    double det = glm::dot(e1, pv);
    if (det == 0 || !std::isfinite(det)) return false;
    Vec3d tv = o - p0, qv = glm::cross(tv, e1);
    b1 = glm::dot(tv, pv) / det;
    b2 = glm::dot(d, qv) / det;
    t = glm::dot(e2, qv) / det;
    return b1 >= -slack && b2 >= -slack && b1 + b2 <= 1 + slack;
}
}  // namespace

PrecisionCheck TruthSurface::checkPrecision(const Camera& camera, const Texture& height,
                                            int samples, uint32_t seed) const {
    const Impl& m = *impl_;
    PrecisionCheck pc;
    std::vector<std::pair<int, int>> pixels;
    for (int y = 0; y < camera.height(); ++y)
        for (int x = 0; x < camera.width(); ++x) pixels.push_back({x, y});
    std::mt19937 rng(seed);
    std::shuffle(pixels.begin(), pixels.end(), rng);
    setTracingFpMode();
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    std::vector<double> errs;
    for (const auto& [x, y] : pixels) {
        if (int64_t(errs.size()) >= samples) break;
        Impl::Detail det;
        TruthSample s = m.trace(camera.pixelRay(x, y), &ctx, &det);
        if (!s.hit) continue;
        uint32_t tri[2][3];
        int n = m.candidates(det.rh, tri);
        // Re-intersect the hit triangle in double (the same float vertices, the unrounded
        // ray); a grid cell's two triangles are both tried, the nearer inside one wins.
        double bestT = INFINITY;
        Vec2d uv(0);
        for (int k = 0; k < n; ++k) {
            Vec3d p[3];
            for (int c = 0; c < 3; ++c) p[c] = Vec3d(m.vertices[tri[k][c]]);
            double t, b1, b2;
            // A slack of 1e-6 in barycentrics accepts Embree's float hits on a shared edge
            // (float rounding of the vertices is about 1e-7 of their size).
            if (!intersectDouble(det.org, det.dir, p[0], p[1], p[2], 1e-6, t, b1, b2)) continue;
            if (t < bestT) {
                bestT = t;
                uv = m.base->uvAt(tri[k][0]) * (1 - b1 - b2) + m.base->uvAt(tri[k][1]) * b1 +
                     m.base->uvAt(tri[k][2]) * b2 + det.uvOffset;
            }
        }
        if (!std::isfinite(bestT)) {
            ++pc.edgeMisses;  // the float hit lies on an edge the double ray just misses
            continue;
        }
        errs.push_back(uvErrorTexels(s.uv, uv, height.width, height.height, height.address));
    }
    pc.samples = int64_t(errs.size());
    if (!errs.empty()) {  // else the 0s of PrecisionCheck: nothing was sampled
        Summary e = summarize(errs);
        pc.p50Texels = e.p50, pc.p99Texels = e.p99, pc.maxTexels = e.max;
    }
    return pc;
}

}  // namespace pgt
