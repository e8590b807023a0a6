// Uniform OpenSubdiv refinement of a control mesh into the rasterised triangle mesh, and the
// Listing 7.4 tangent frames of that mesh.
#include "mesh/refine.h"

#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <cmath>
#include <map>
#include <memory>
#include <stdexcept>

#include "mesh/osd_refiner.h"

namespace pgt {

std::string toString(Scheme s) {
    return s == Scheme::Bilinear ? "bilinear" : s == Scheme::Catmark ? "catmark" : "loop";
}

std::vector<float> computeTangentFrames(BaseMesh& mesh, TangentFrameStats* stats) {
    const size_t n = mesh.vertices.size();
    std::vector<Vec3d> tan(n, Vec3d(0)), bit(n, Vec3d(0));
    TangentFrameStats st;
    for (size_t k = 0; k + 2 < mesh.indices.size(); k += 3) {
        uint32_t i0 = mesh.indices[k], i1 = mesh.indices[k + 1], i2 = mesh.indices[k + 2];
        const BaseVertex &a = mesh.vertices[i0], &b = mesh.vertices[i1], &c = mesh.vertices[i2];
        Vec3d e1 = b.position - a.position, e2 = c.position - a.position;
        double x1 = b.uv.x - a.uv.x, x2 = c.uv.x - a.uv.x;
        double y1 = b.uv.y - a.uv.y, y2 = c.uv.y - a.uv.y;
        double det = x1 * y2 - x2 * y1;
        // Listing 7.4 divides by det unguarded; a (near-)zero UV area makes t and b infinite.
        // Relative to the UV edge lengths, 1e-12 is far below any texel of a real map.
        double scale = std::max({x1 * x1 + y1 * y1, x2 * x2 + y2 * y2, 1e-300});
        if (!(std::fabs(det) > 1e-12 * scale)) {
            ++st.degenerateUvTriangles;
            continue;
        }
        double r = 1.0 / det;
        Vec3d t = (e1 * y2 - e2 * y1) * r;  // Eq. 7.37
        Vec3d bb = (e2 * x1 - e1 * x2) * r;
        for (uint32_t i : {i0, i1, i2}) tan[i] += t, bit[i] += bb;
    }
    std::vector<float> w(n, 1.0f);
    for (size_t i = 0; i < n; ++i) {
        BaseVertex& v = mesh.vertices[i];
        Vec3d nrm = glm::normalize(v.normal);
        Vec3d t = tan[i] - nrm * glm::dot(tan[i], nrm);  // Eq. 7.38 (Reject)
        double len = glm::length(t);
        // The tangent is (anti)parallel to n when its rejection keeps less than 1e-12 of its
        // length (the same relative bound as the UV area above).
        if (!(len > 1e-12 * (glm::length(tan[i]) + 1e-300)) || !std::isfinite(len)) {
            // No usable tangent: any unit vector perpendicular to n keeps the frame finite.
            ++st.fallbackTangents;
            Vec3d axis = std::fabs(nrm.x) < 0.9 ? Vec3d(1, 0, 0) : Vec3d(0, 1, 0);
            t = glm::normalize(axis - nrm * glm::dot(axis, nrm));
        } else {
            t /= len;
        }
        w[i] = glm::dot(glm::cross(tan[i], bit[i]), nrm) > 0.0 ? 1.0f : -1.0f;
        if (w[i] < 0) ++st.mirroredVertices;
        v.normal = nrm;
        v.tangent = t;
        v.bitangent = glm::cross(nrm, t) * double(w[i]);  // Eq. 7.40
        v.handedness = w[i];
    }
    if (stats) *stats = st;
    return w;
}

namespace {

struct Point3 {
    Vec3d p{0};
    void Clear(void* = nullptr) { p = Vec3d(0); }
    void AddWithWeight(const Point3& s, double w) { p += s.p * w; }
};
struct Point2 {
    Vec2d p{0};
    void Clear(void* = nullptr) { p = Vec2d(0); }
    void AddWithWeight(const Point2& s, double w) { p += s.p * w; }
};

}  // namespace

std::unique_ptr<OpenSubdiv::Far::TopologyRefiner> createRefiner(const ControlMesh& cage,
                                                                Scheme scheme) {
    using namespace OpenSubdiv;
    if (scheme == Scheme::Loop)
        for (int n : cage.faceSizes)
            if (n != 3) throw std::invalid_argument("the loop scheme needs a triangle mesh");
    Far::TopologyDescriptor desc;
    desc.numVertices = int(cage.positions.size());
    desc.numFaces = cage.numFaces();
    desc.numVertsPerFace = cage.faceSizes.data();
    desc.vertIndicesPerFace = cage.faceVerts.data();
    Far::TopologyDescriptor::FVarChannel uvChannel;
    uvChannel.numValues = int(cage.uvs.size());
    uvChannel.valueIndices = cage.faceUvs.data();
    desc.numFVarChannels = 1;
    desc.fvarChannels = &uvChannel;
    Sdc::Options sdc;
    sdc.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER);
    sdc.SetFVarLinearInterpolation(Sdc::Options::FVAR_LINEAR_ALL);  // UVs stay piecewise linear
    Sdc::SchemeType type = scheme == Scheme::Bilinear  ? Sdc::SCHEME_BILINEAR
                           : scheme == Scheme::Catmark ? Sdc::SCHEME_CATMARK
                                                       : Sdc::SCHEME_LOOP;
    using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
    std::unique_ptr<Far::TopologyRefiner> refiner(
        Factory::Create(desc, Factory::Options(type, sdc)));
    if (!refiner) throw std::invalid_argument("OpenSubdiv rejected the control mesh's topology");
    return refiner;
}

RefinedMesh refineToTriangles(const ControlMesh& cage, Scheme scheme, int levels) {
    using namespace OpenSubdiv;
    std::unique_ptr<Far::TopologyRefiner> refiner = createRefiner(cage, scheme);
    Far::TopologyRefiner::UniformOptions uniform(levels);
    uniform.fullTopologyInLastLevel = true;
    refiner->RefineUniform(uniform);

    // Interpolate positions and UVs level by level.
    std::vector<Point3> pos(refiner->GetNumVerticesTotal());
    std::vector<Point2> uv(refiner->GetNumFVarValuesTotal(0));
    for (size_t k = 0; k < cage.positions.size(); ++k) pos[k].p = cage.positions[k];
    for (size_t k = 0; k < cage.uvs.size(); ++k) uv[k].p = cage.uvs[k];
    Far::PrimvarRefinerReal<double> primvar(*refiner);
    Point3* srcP = pos.data();
    Point2* srcT = uv.data();
    for (int level = 1; level <= levels; ++level) {
        Point3* dstP = srcP + refiner->GetLevel(level - 1).GetNumVertices();
        Point2* dstT = srcT + refiner->GetLevel(level - 1).GetNumFVarValues(0);
        primvar.Interpolate(level, srcP, dstP);
        primvar.InterpolateFaceVarying(level, srcT, dstT);
        srcP = dstP, srcT = dstT;
    }
    const Far::TopologyLevel& last = refiner->GetLevel(levels);
    const int nv = last.GetNumVertices();
    std::vector<Point3> finalPos(srcP, srcP + nv), limitNormal;
    std::vector<Point2> finalUv(srcT, srcT + last.GetNumFVarValues(0));
    bool smooth = scheme != Scheme::Bilinear;
    if (smooth) {
        // The drawn vertices sit on the limit surface; its normals are exact there.
        std::vector<Point3> limitPos(nv), du(nv), dv(nv);
        primvar.Limit(srcP, limitPos, du, dv);
        std::vector<Point2> limitUv(finalUv.size());
        primvar.LimitFaceVarying(srcT, limitUv);
        finalPos = limitPos;
        finalUv = limitUv;
        limitNormal.resize(nv);
        for (int k = 0; k < nv; ++k) limitNormal[k].p = glm::cross(du[k].p, dv[k].p);
    }

    RefinedMesh out;
    BaseMesh& m = out.mesh;
    std::map<std::pair<int, int>, uint32_t> vertexOf;  // (position, uv) -> output vertex
    std::vector<Vec3d> areaNormal;                     // per output vertex (bilinear)
    std::vector<Vec3d> positionNormal(nv, Vec3d(0));   // per position: orientation reference
    for (int f = 0; f < last.GetNumFaces(); ++f) {
        auto fv = last.GetFaceVertices(f);
        auto ft = last.GetFaceFVarValues(f, 0);
        std::vector<uint32_t> corners;
        for (int c = 0; c < fv.size(); ++c) {
            auto key = std::make_pair(int(fv[c]), int(ft[c]));
            auto it = vertexOf.find(key);
            if (it == vertexOf.end()) {
                BaseVertex v;
                v.position = finalPos[fv[c]].p;
                v.uv = finalUv[ft[c]].p;
                it = vertexOf.emplace(key, uint32_t(m.vertices.size())).first;
                m.vertices.push_back(v);
                areaNormal.push_back(Vec3d(0));
            }
            corners.push_back(it->second);
        }
        for (size_t k = 1; k + 1 < corners.size(); ++k) {
            uint32_t a = corners[0], b = corners[k], c = corners[k + 1];
            m.indices.insert(m.indices.end(), {a, b, c});
            Vec3d fn = glm::cross(m.vertices[b].position - m.vertices[a].position,
                                  m.vertices[c].position - m.vertices[a].position);
            for (uint32_t i : {a, b, c}) areaNormal[i] += fn;  // area-weighted
            for (int cc : {0, int(k), int(k + 1)}) positionNormal[fv[cc]] += fn;
        }
    }
    for (auto& [key, idx] : vertexOf) {
        Vec3d n = areaNormal[idx];  // bilinear: smooth within a UV chart, split at seams
        if (smooth) {
            n = limitNormal[key.first].p;
            if (glm::dot(n, positionNormal[key.first]) < 0) n = -n;  // face orientation
        }
        double len = glm::length(n);
        m.vertices[idx].normal = len > 0 && std::isfinite(len) ? n / len : Vec3d(0, 0, 1);
    }
    out.handedness = computeTangentFrames(m, &out.frames);
    return out;
}

}  // namespace pgt
