// Base tessellations for the truth: a plane's lattice from OpenSubdiv Bfr's bilinear quad,
// a mesh's drawn triangles split n x n, and the limit surface tessellated face by face with
// Bfr's Tessellation API; the part of a plane a view can see.
#include "truth/tessellation.h"

#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/bfr/tessellation.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <tuple>
#include <vector>

#include "core/clock.h"
#include "core/error.h"
#include "core/format.h"
#include "core/interrupt.h"
#include "core/memory.h"
#include "mesh/osd_refiner.h"

namespace pgt {

TexelRange texelRange(const Texture& height) {
    // Over every texel, on every core, polling the cancel flag: a 16384^2 map is a gigabyte
    // (Ctrl-C in Python waited 8 s on this loop, serial).
    using Range = std::pair<float, float>;
    const auto [lo, hi] = tbb::parallel_reduce(
        tbb::blocked_range<size_t>(0, height.texels.size(), size_t(1) << 20), Range{1e30f, -1e30f},
        [&](const tbb::blocked_range<size_t>& r, Range acc) {
            throwIfCancelled();
            for (size_t k = r.begin(); k < r.end(); ++k)
                acc.first = std::min(acc.first, height.texels[k]),
                acc.second = std::max(acc.second, height.texels[k]);
            return acc;
        },
        [](Range a, const Range& b) {
            return Range{std::min(a.first, b.first), std::max(a.second, b.second)};
        });
    return {lo, hi};
}

TruthWindow viewWindow(const PlaneBase& plane, const Texture& height, const Displacement& disp,
                       const Camera& camera, const std::optional<Vec3d>& light, PixelRect block,
                       double reach, const TexelRange* range) {
    constexpr double kMarginTexels = 2;
    if (block.empty()) block = {0, 0, camera.width(), camera.height()};
    TruthWindow w;
    const TexelRange slab = range ? *range : texelRange(height);
    const float hMin = slab.lo, hMax = slab.hi;
    const double l = plane.worldPerUv();
    const double z[2] = {plane.center.z + l * (disp.scale * hMin + disp.bias),
                         plane.center.z + l * (disp.scale * hMax + disp.bias)};
    // The frustum's four edge rays through the frame's corners meet each slab plane in a
    // quadrilateral; every ray of the frame crosses the slab inside their hull.
    Vec2d lo(1e300), hi(-1e300);
    const double x0 = block.x0, x1 = block.x1, y0 = block.y0, y1 = block.y1;
    for (Vec2d c : {Vec2d(x0, y0), Vec2d(x1, y0), Vec2d(x0, y1), Vec2d(x1, y1)}) {
        Ray r = camera.ray(c.x, c.y);
        if (!(std::fabs(r.dir.z) > 1e-9)) return {};  // parallel to the plane: unbounded
        for (double zk : z) {
            double t = (zk - r.origin.z) / r.dir.z;
            if (!r.line && t < 0) return {};  // behind a pinhole eye: unbounded
            Vec3d p = r.origin + r.dir * t;
            Vec2d uv((p.x - plane.center.x) / l + plane.tiling / 2,
                     (p.y - plane.center.y) / l + plane.tiling / 2);
            lo = glm::min(lo, uv), hi = glm::max(hi, uv);
        }
    }
    // Shadow rays rise from a hit toward the light until they leave the slab: at most
    // (z_hi - z_lo) / L.z along the light, L.xy / L.z per unit of height (docs/model.md §5b).
    // A light at or below the horizon traces none (every hit is dark).
    if (light && light->z > 0) {
        const Vec3d L = *light;
        const Vec2d toward = Vec2d(L.x, L.y) * ((z[1] - z[0]) / L.z / l * reach);
        lo = glm::min(lo, lo + toward), hi = glm::max(hi, hi + toward);
    }
    Vec2d margin = Vec2d(kMarginTexels / height.width, kMarginTexels / height.height) * reach;
    lo -= margin, hi += margin;
    if (!plane.infinite) lo = glm::max(lo, Vec2d(0)), hi = glm::min(hi, Vec2d(plane.tiling));
    w.limited = true;
    w.empty = !(lo.x < hi.x && lo.y < hi.y);
    w.uvMin = lo;
    w.uvMax = hi;
    return w;
}

TruthWindow frameWindow(const PlaneBase& plane, const Texture& height, const Displacement& disp,
                        const Camera& camera, const std::optional<Vec3d>& light, PixelRect block,
                        double reach, const TexelRange* range) {
    TruthWindow w = viewWindow(plane, height, disp, camera, light, block, reach, range);
    const double T = plane.tiling;
    const Vec2d extent = w.uvMax - w.uvMin;
    if (w.empty || (block.empty() && w.limited && extent.x * extent.y >= 0.5 * T * T)) return {};
    return w;
}

namespace {

// The grid's corners, normal and UV shape from OpenSubdiv: the base plane as a one-quad
// bilinear control mesh with face-varying UVs, control points relative to the plane centre
// (the local frame of the float vertices). Checks that Bfr's pattern at the grid's rates
// is the lattice the grid indexes.
void evaluatePlaneCorners(const PlaneBase& plane, PlaneGrid& g) {
    using namespace OpenSubdiv;
    const double half = plane.size / 2, tiling = plane.tiling;
    ControlMesh quad;
    quad.positions = {{-half, -half, 0}, {half, -half, 0}, {half, half, 0}, {-half, half, 0}};
    quad.uvs = {{0, 0}, {tiling, 0}, {tiling, tiling}, {0, tiling}};
    quad.faceSizes = {4};
    quad.faceVerts = {0, 1, 2, 3};
    quad.faceUvs = {0, 1, 2, 3};
    std::unique_ptr<Far::TopologyRefiner> refiner = createRefiner(quad, Scheme::Bilinear);
    Bfr::RefinerSurfaceFactory<> factory(*refiner,
                                         Bfr::SurfaceFactory::Options().SetDefaultFVarID(0));
    Bfr::Surface<double> posSurface, uvSurface;
    PGT_CHECK(factory.InitVertexSurface(0, &posSurface));
    PGT_CHECK(factory.InitFaceVaryingSurface(0, &uvSurface));

    int rates[4] = {g.nu, g.nv, g.nu, g.nv};  // quad edges: v0v1 (u), v1v2 (v), v2v3, v3v0
    // Bfr's pattern for these rates is the regular lattice the grid indexes (checked where
    // its int count can hold it; windows of larger lattices use the same formula). Bfr
    // clamps an edge rate to kBfrMaxRate (measured: rates 40000 x 4 gave 32768 x 5
    // coordinates), so wider lattices, e.g. a 20000-texel map at 2x rate, are not compared.
    constexpr int kBfrMaxRate = 32767;
    if (int64_t(g.nu + 1) * (g.nv + 1) < (int64_t(1) << 30) && g.nu <= kBfrMaxRate &&
        g.nv <= kBfrMaxRate) {
        Bfr::Tessellation tess(posSurface.GetParameterization(), 4, rates,
                               Bfr::Tessellation::Options().SetFacetSize(4).PreserveQuads(true));
        PGT_CHECK(tess.IsValid());
        PGT_CHECK_EQ(int64_t(tess.GetNumCoords()), int64_t(g.nu + 1) * (g.nv + 1));
    }

    std::vector<double> posPatch(size_t(posSurface.GetNumPatchPoints()) * 3);
    std::vector<double> uvPatch(size_t(uvSurface.GetNumPatchPoints()) * 2);
    posSurface.PreparePatchPoints(&quad.positions[0].x, 3, posPatch.data(), 3);
    uvSurface.PreparePatchPoints(&quad.uvs[0].x, 2, uvPatch.data(), 2);
    // The corners of the pattern; every other vertex is their bilinear blend (PlaneGrid).
    const double corners[4][2] = {{0, 0}, {1, 0}, {0, 1}, {1, 1}};
    for (int c = 0; c < 4; ++c) {
        double P[3], Du[3], Dv[3], UV[2];
        posSurface.Evaluate(corners[c], posPatch.data(), 3, P, Du, Dv);
        uvSurface.Evaluate(corners[c], uvPatch.data(), 2, UV);
        g.cornerPosition[c] = Vec3d(P[0], P[1], P[2]);
        g.cornerUv[c] = Vec2d(UV[0], UV[1]);
        if (c == 0)
            g.planeNormal =
                glm::normalize(glm::cross(Vec3d(Du[0], Du[1], Du[2]), Vec3d(Dv[0], Dv[1], Dv[2])));
    }
    // A parallelogram up to double rounding of the corners' UVs (1e-12 of their extent).
    const Vec2d skew = g.cornerUv[0] + g.cornerUv[3] - g.cornerUv[1] - g.cornerUv[2];
    g.affineUv = glm::length(skew) <= 1e-12 * (1 + glm::length(g.cornerUv[3] - g.cornerUv[0]));
}

}  // namespace

std::shared_ptr<const BaseTessellation> tessellatePlane(const Texture& height,
                                                        const PlaneBase& plane, int rate,
                                                        const TruthWindow& window) {
    return tessellatePlane(std::make_shared<const Texture>(height), plane, rate, window);
}

std::shared_ptr<const BaseTessellation> tessellatePlane(std::shared_ptr<const Texture> shared,
                                                        const PlaneBase& plane, int rate,
                                                        const TruthWindow& window) {
    const Texture& height = *shared;
    auto t0 = Clock::now();
    auto out = std::make_shared<BaseTessellation>();
    BaseTessellation& m = *out;
    PlaneGrid& g = m.grid.emplace();
    m.origin = plane.center;
    m.worldPerUv = plane.worldPerUv();
    m.periodWorld = plane.size;
    m.periodUv = plane.tiling;
    // `rate` samples per texel per axis over the texels the plane covers.
    const PlaneLattice lattice(plane, height, rate);
    // The scene parser bounds the sides; this keeps the int conversion defined.
    PGT_CHECK_LT(std::max(lattice.nu, lattice.nv), double(int64_t(1) << 30));
    g.nu = g.fullNu = int(lattice.nu);
    g.nv = g.fullNv = int(lattice.nv);
    g.invNu = 1.0 / g.nu;
    g.invNv = 1.0 / g.nv;
    evaluatePlaneCorners(plane, g);
    g.heightMap = std::move(shared);
    if (window.limited) {
        // The lattice vertices covering the window (whole cells of the tile's lattice, so
        // the window's sheet is the very same surface as the tile's).
        const PlaneLattice::Span su = lattice.span(window.uvMin.x, window.uvMax.x, lattice.nu);
        const PlaneLattice::Span sv = lattice.span(window.uvMin.y, window.uvMax.y, lattice.nv);
        g.offsetI = int(su.first), g.nu = int(su.count);
        g.offsetJ = int(sv.first), g.nv = int(sv.count);
    }
    // What is built: the memory estimate refuses a larger lattice before any work.
    PGT_CHECK_LT((double(g.nu) + 1) * (double(g.nv) + 1), double(int64_t(1) << 32));
    m.tessellateMs = msSince(t0);
    return out;
}

Vec3d BaseTessellation::positionAt(size_t k) const {
    if (!isGrid()) return Vec3d(sheet.position[k]);
    size_t w = size_t(grid->nu) + 1;
    return PlaneGrid::blend(grid->cornerPosition, grid->gridS(int(k % w)), grid->gridT(int(k / w)));
}

Vec3d BaseTessellation::normalAt(size_t k) const {
    return isGrid() ? grid->planeNormal : Vec3d(sheet.normal[k]);
}

Vec2d BaseTessellation::uvAt(size_t k) const {
    if (!isGrid()) return sheet.uv[k];
    size_t w = size_t(grid->nu) + 1;
    return grid->gridUv(int(k % w), int(k / w));
}

double BaseTessellation::heightAt(size_t k) const {
    return isGrid() ? sampleBilinear<double>(*grid->heightMap, uvAt(k)) : sheet.height[k];
}

size_t BaseTessellation::bytes() const {
    return sheet.position.size() * sizeof(Vec3f) + sheet.normal.size() * sizeof(Vec3f) +
           sheet.uv.size() * sizeof(Vec2d) + sheet.height.size() * sizeof(double) +
           sheet.triangles.size() * sizeof(uint32_t) +
           (isGrid() && grid->heightMap ? grid->heightMap->texels.size() * sizeof(float) : 0);
}

std::shared_ptr<const BaseTessellation> tessellateLimitSurface(const Texture& height,
                                                               const ControlMesh& cage,
                                                               Scheme scheme, double worldPerUv,
                                                               int rate) {
    using namespace OpenSubdiv;
    auto t0 = Clock::now();
    auto out = std::make_shared<BaseTessellation>();
    BaseTessellation& m = *out;
    m.worldPerUv = worldPerUv;
    Vec3d lo(1e300), hi(-1e300);
    for (const auto& p : cage.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
    m.origin = (lo + hi) * 0.5;

    std::unique_ptr<Far::TopologyRefiner> refiner = createRefiner(cage, scheme);
    const Far::TopologyLevel& level = refiner->GetLevel(0);
    Bfr::RefinerSurfaceFactory<> factory(*refiner,
                                         Bfr::SurfaceFactory::Options().SetDefaultFVarID(0));

    // Rate per cage edge: its longest UV image in texels x rate (the max over both sides).
    std::vector<int> edgeRate(level.GetNumEdges(), 1);
    for (int f = 0; f < level.GetNumFaces(); ++f) {
        auto fe = level.GetFaceEdges(f);
        auto ft = level.GetFaceFVarValues(f, 0);
        for (int i = 0; i < fe.size(); ++i) {
            Vec2d a = cage.uvs[ft[i]], b = cage.uvs[ft[(i + 1) % fe.size()]];
            double texels = glm::length((b - a) * Vec2d(height.width, height.height));
            // (capped in double: a UV edge millions of texels long must not overflow an int)
            double r = std::min(std::ceil(rate * texels - 1e-9), double(1 << 15));
            edgeRate[fe[i]] = std::max(edgeRate[fe[i]], int(r));
        }
    }

    std::map<std::pair<int, int>, uint32_t> cornerOf;           // (vertex, uv value)
    std::map<std::tuple<int, int, int, int>, uint32_t> edgeOf;  // (edge, k, uvA, uvB)
    auto push = [&](const Vec3d& p, const Vec3d& n, const Vec2d& uv) {
        m.sheet.position.push_back(Vec3f(p - m.origin));
        m.sheet.normal.push_back(Vec3f(n));
        m.sheet.uv.push_back(uv);
        m.sheet.height.push_back(sampleBilinear<double>(height, uv));
        return uint32_t(m.sheet.position.size() - 1);
    };
    Bfr::Surface<double> pos, tex;
    std::vector<double> posPatch, uvPatch, coords;
    std::vector<int> facets;
    for (int f = 0; f < level.GetNumFaces(); ++f) {
        if (!factory.InitVertexSurface(f, &pos) || !factory.InitFaceVaryingSurface(f, &tex))
            continue;  // holes have no limit surface
        auto fv = level.GetFaceVertices(f);
        auto fe = level.GetFaceEdges(f);
        auto ft = level.GetFaceFVarValues(f, 0);
        const int nEdges = fe.size();
        std::vector<int> rates(nEdges);
        for (int i = 0; i < nEdges; ++i) rates[i] = edgeRate[fe[i]];
        Bfr::Tessellation tess(pos.GetParameterization(), nEdges, rates.data(),
                               Bfr::Tessellation::Options().SetFacetSize(3));
        PGT_CHECK(tess.IsValid());
        coords.resize(size_t(tess.GetNumCoords()) * 2);
        tess.GetCoords(coords.data());
        posPatch.resize(size_t(pos.GetNumPatchPoints()) * 3);
        uvPatch.resize(size_t(tex.GetNumPatchPoints()) * 2);
        pos.PreparePatchPoints(&cage.positions[0].x, 3, posPatch.data(), 3);
        tex.PreparePatchPoints(&cage.uvs[0].x, 2, uvPatch.data(), 2);
        auto evaluate = [&](const double* st) {
            double P[3], Du[3], Dv[3], UV[2];
            pos.Evaluate(st, posPatch.data(), 3, P, Du, Dv);
            tex.Evaluate(st, uvPatch.data(), 2, UV);
            Vec3d n = glm::cross(Vec3d(Du[0], Du[1], Du[2]), Vec3d(Dv[0], Dv[1], Dv[2]));
            double len = glm::length(n);
            return push(Vec3d(P[0], P[1], P[2]), len > 0 ? n / len : Vec3d(0, 0, 1),
                        Vec2d(UV[0], UV[1]));
        };
        // Map each coordinate of the pattern to a shared or new vertex: corners by
        // (vertex, uv value), edge points by (edge, k from the edge's first vertex, uv values
        // at both ends), interior points new.
        std::map<std::pair<double, double>, uint32_t> vertexAt;
        std::vector<double> buf(
            size_t(std::max(2, 2 * (*std::max_element(rates.begin(), rates.end()) + 1))));
        for (int i = 0; i < nEdges; ++i) {
            tess.GetVertexCoord(i, buf.data());
            auto key = std::make_pair(int(fv[i]), int(ft[i]));
            auto it = cornerOf.find(key);
            if (it == cornerOf.end()) it = cornerOf.emplace(key, evaluate(buf.data())).first;
            vertexAt[{buf[0], buf[1]}] = it->second;
        }
        for (int i = 0; i < nEdges; ++i) {
            int count = tess.GetEdgeCoords(i, buf.data());
            auto ev = level.GetEdgeVertices(fe[i]);
            bool forward = ev[0] == fv[i];
            int uvA = forward ? ft[i] : ft[(i + 1) % nEdges];
            int uvB = forward ? ft[(i + 1) % nEdges] : ft[i];
            for (int k = 0; k < count; ++k) {
                int along = forward ? k : count - 1 - k;  // from the edge's first vertex
                auto key = std::make_tuple(int(fe[i]), along, uvA, uvB);
                auto it = edgeOf.find(key);
                if (it == edgeOf.end()) it = edgeOf.emplace(key, evaluate(&buf[2 * k])).first;
                vertexAt[{buf[2 * k], buf[2 * k + 1]}] = it->second;
            }
        }
        std::vector<uint32_t> index(coords.size() / 2);
        for (size_t c = 0; c < index.size(); ++c) {
            auto it = vertexAt.find({coords[2 * c], coords[2 * c + 1]});
            index[c] = it != vertexAt.end() ? it->second : evaluate(&coords[2 * c]);
        }
        facets.resize(size_t(tess.GetNumFacets()) * 3);
        tess.GetFacets(facets.data());
        for (size_t k = 0; k + 2 < facets.size(); k += 3)
            m.sheet.triangles.insert(
                m.sheet.triangles.end(),
                {index[facets[k]], index[facets[k + 1]], index[facets[k + 2]]});
    }
    PGT_CHECK(!m.sheet.triangles.empty());
    m.tessellateMs = msSince(t0);
    return out;
}

namespace {

// A drawn mesh's segment counts for its polygonal truth: every edge rate x its UV length in
// texels, every triangle its longest edge's count, all lowered by one factor for the whole
// mesh where the vertex count would pass maxVertices.
class DrawnSegments {
  public:
    using EdgeKey = std::pair<uint32_t, uint32_t>;  // drawn vertex indices, smaller first
    DrawnSegments(const BaseMesh& drawn, const Texture& height, int rate, int64_t maxVertices)
        : drawn_(drawn), texelsPerUv_(height.width, height.height), rate_(rate) {
        while (vertices() > double(maxVertices) && factor_ >= 1e-6) factor_ *= 0.9;
    }
    // The sheet's vertices at the current counts (each triangle's lattice counted whole: an
    // upper bound, shared edge points counted twice).
    double vertices() const {
        double verts = 0;
        for (size_t t = 0; t < drawn_.indices.size() / 3; ++t) {
            const double n = triangle(t);
            verts += (n + 1) * (n + 2) / 2;
        }
        return verts;
    }
    // An edge's count, from its UV length in texels (the same from either triangle).
    int edge(const EdgeKey& k) const {
        const double texels = glm::length(
            (drawn_.vertices[k.second].uv - drawn_.vertices[k.first].uv) * texelsPerUv_);
        const double n = std::ceil(factor_ * rate_ * texels - 1e-9);
        return std::max(1, int(std::min(n, double(1 << 15))));
    }
    int triangle(size_t t) const {
        const uint32_t* i = &drawn_.indices[3 * t];
        auto key = [](uint32_t a, uint32_t b) { return EdgeKey(std::min(a, b), std::max(a, b)); };
        return std::max({edge(key(i[0], i[1])), edge(key(i[1], i[2])), edge(key(i[2], i[0]))});
    }

  private:
    const BaseMesh& drawn_;
    Vec2d texelsPerUv_;
    int rate_;
    double factor_ = 1;
};

}  // namespace

void checkMeshTruthMemory(const Scene& s) {
    const MeshBase* mesh = std::get_if<MeshBase>(&s.base);
    if (mesh && mesh->truthSurface == MeshTruth::Polygonal) {
        const int rate = s.truth.rate;
        const double verts =
            drawnTruthVertices(s.height, mesh->drawn->mesh, rate) +
            (s.truth.uncertainty ? drawnTruthVertices(s.height, mesh->drawn->mesh, 2 * rate) : 0);
        checkMemory(verts * kTruthBytesPerSheetVertex, s.file, "truth.rate", std::to_string(rate),
                    "the mesh's polygonal truth (about " + formatNumber(verts, 3) +
                        " vertices: every drawn edge split at rate points per texel of its UV "
                        "length" +
                        (s.truth.uncertainty ? ", and at 2 x rate for the uncertainty" : "") + ")");
    }
}

double drawnTruthVertices(const Texture& height, const BaseMesh& drawn, int rate) {
    return DrawnSegments(drawn, height, rate, std::numeric_limits<int64_t>::max()).vertices();
}

std::shared_ptr<const BaseTessellation> tessellateDrawnMesh(const Texture& height,
                                                            const BaseMesh& drawn,
                                                            double worldPerUv, int rate,
                                                            int64_t maxVertices) {
    auto t0 = Clock::now();
    auto out = std::make_shared<BaseTessellation>();
    BaseTessellation& m = *out;
    m.worldPerUv = worldPerUv;
    const size_t nTri = drawn.indices.size() / 3;
    PGT_CHECK(nTri > 0);
    Vec3d lo(1e300), hi(-1e300);
    for (const auto& v : drawn.vertices)
        lo = glm::min(lo, v.position), hi = glm::max(hi, v.position);
    m.origin = (lo + hi) * 0.5;
    const DrawnSegments seg(drawn, height, rate, maxVertices);
    using EdgeKey = DrawnSegments::EdgeKey;
    struct EdgePoints {
        uint32_t first = 0;  // the first of n - 1 points, from the key's first vertex
        int n = 1;
    };
    std::map<EdgeKey, EdgePoints> edges;
    auto addVertex = [&](const BaseVertex& a, const BaseVertex& b, const BaseVertex& c, double wa,
                         double wb, double wc) {
        Vec3d p = a.position * wa + b.position * wb + c.position * wc;
        Vec3d nrm = a.normal * wa + b.normal * wb + c.normal * wc;
        double len = glm::length(nrm);
        nrm = len > 0 ? nrm / len : Vec3d(0, 0, 1);
        Vec2d uv = a.uv * wa + b.uv * wb + c.uv * wc;
        m.sheet.position.push_back(Vec3f(p - m.origin));
        m.sheet.normal.push_back(Vec3f(nrm));
        m.sheet.uv.push_back(uv);
        m.sheet.height.push_back(sampleBilinear<double>(height, uv));
        return uint32_t(m.sheet.position.size() - 1);
    };
    // Corners first: drawn vertex i is tessellation vertex i.
    for (const auto& v : drawn.vertices) addVertex(v, v, v, 1, 0, 0);
    std::vector<uint32_t> local;
    for (size_t t = 0; t < nTri; ++t) {
        const uint32_t id[3] = {drawn.indices[3 * t], drawn.indices[3 * t + 1],
                                drawn.indices[3 * t + 2]};
        const BaseVertex* v[3] = {&drawn.vertices[id[0]], &drawn.vertices[id[1]],
                                  &drawn.vertices[id[2]]};
        // Lattice point (i, j), i + j <= n, barycentric (1 - (i+j)/n, i/n, j/n); n from the
        // triangle's longest edge.
        const int n = seg.triangle(t);
        local.assign(size_t(n + 1) * (n + 1), 0);
        auto at = [&](int i, int j) -> uint32_t& { return local[size_t(j) * (n + 1) + i]; };
        at(0, 0) = id[0], at(n, 0) = id[1], at(0, n) = id[2];
        // Edge points, made once per edge at its own count and shared through the pair of
        // drawn vertex indices. A lattice boundary point k of n snaps to the edge's nearest
        // point (k x edge count / n, rounded): the sheet stays watertight where a longer
        // neighbour's lattice is finer, at the cost of zero-area strip triangles there.
        auto edge = [&](int ea, int eb, auto point) {
            const EdgeKey key(std::min(id[ea], id[eb]), std::max(id[ea], id[eb]));
            const bool flip = id[ea] > id[eb];
            auto it = edges.find(key);
            if (it == edges.end()) {
                EdgePoints e{uint32_t(m.sheet.position.size()), seg.edge(key)};
                const BaseVertex& lo0 = drawn.vertices[key.first];
                const BaseVertex& hi0 = drawn.vertices[key.second];
                for (int k = 1; k < e.n; ++k)
                    addVertex(lo0, hi0, hi0, 1.0 - double(k) / e.n, double(k) / e.n, 0.0);
                it = edges.emplace(key, e).first;
            }
            const EdgePoints& e = it->second;
            for (int k = 1; k < n; ++k) {
                const int fromA = int(std::lround(double(k) * e.n / n));  // from id[ea]
                const int fromLo = flip ? e.n - fromA : fromA;
                point(k) = fromLo == 0     ? key.first
                           : fromLo == e.n ? key.second
                                           : e.first + uint32_t(fromLo - 1);
            }
        };
        edge(0, 1, [&](int k) -> uint32_t& { return at(k, 0); });
        edge(0, 2, [&](int k) -> uint32_t& { return at(0, k); });
        edge(1, 2, [&](int k) -> uint32_t& { return at(n - k, k); });
        for (int j = 1; j < n; ++j)
            for (int i = 1; i + j < n; ++i)
                at(i, j) = addVertex(*v[0], *v[1], *v[2], 1.0 - double(i + j) / n, double(i) / n,
                                     double(j) / n);
        auto emit = [&](uint32_t a, uint32_t b, uint32_t c) {
            if (a != b && b != c && a != c)
                m.sheet.triangles.insert(m.sheet.triangles.end(), {a, b, c});
        };
        for (int j = 0; j < n; ++j)
            for (int i = 0; i + j < n; ++i) {
                emit(at(i, j), at(i + 1, j), at(i, j + 1));
                if (i + j + 1 < n) emit(at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            }
    }
    m.tessellateMs = msSince(t0);
    return out;
}

}  // namespace pgt
