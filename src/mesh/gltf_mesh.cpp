// glTF 2.0 primitives (mesh/gltf_mesh.h). tinygltf parses the JSON and the buffers; every
// range, index and value is checked here before it is used, because tinygltf does not check
// accessors against their buffers.
#include "mesh/gltf_mesh.h"

#include <OpenImageIO/hash.h>
#include <tiny_gltf.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <map>
#include <set>
#include <sstream>

#include "core/error.h"
#include "core/interrupt.h"
#include "core/json_read.h"
#include "mesh/gltf_file.h"
#include "mesh/mikktspace.h"

namespace pgt {

using Vec4d = glm::dvec4;
using Mat3d = glm::dmat3;
using Mat4d = glm::dmat4;

std::string toString(MeshFrames frames) {
    return frames == MeshFrames::Asset        ? "asset"
           : frames == MeshFrames::MikkTSpace ? "mikktspace"
                                              : "pgt";
}

namespace {

using Fail = GltfFail;

// A number as a message shows it: 0, 1, -0.5, 1e-07 (not 0.000000).
std::string shortNumber(double x) {
    std::ostringstream os;
    os << x;
    return os.str();
}

std::string accessorName(int index, const std::string& attribute) {
    return "accessor " + std::to_string(index) + " (" + attribute + ")";
}

// One component at p as glTF defines it (normalized integers map to [0, 1] or [-1, 1]).
double component(const unsigned char* p, int type, bool normalized) {
    auto load = [p](auto v) {
        std::memcpy(&v, p, sizeof v);
        return double(v);
    };
    switch (type) {
        case TINYGLTF_COMPONENT_TYPE_FLOAT:
            return load(float());
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            return normalized ? *p / 255.0 : *p;
        case TINYGLTF_COMPONENT_TYPE_BYTE:
            return normalized ? std::max(int8_t(*p) / 127.0, -1.0) : int8_t(*p);
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
            return normalized ? load(uint16_t()) / 65535.0 : load(uint16_t());
        case TINYGLTF_COMPONENT_TYPE_SHORT:
            return normalized ? std::max(load(int16_t()) / 32767.0, -1.0) : load(int16_t());
        default:
            return load(uint32_t());  // TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT
    }
}

// Where an accessor's elements are, after checking that every byte it reads lies in its
// buffer view and buffer, and that its type is one glTF allows for vertex data.
struct AccessorBytes {
    const unsigned char* base = nullptr;
    size_t stride = 0, componentBytes = 0;
};
AccessorBytes locate(const tinygltf::Model& model, const tinygltf::Accessor& a,
                     const std::string& name, int components, const Fail& fail) {
    static const std::set<int> kTypes = {
        TINYGLTF_COMPONENT_TYPE_BYTE,  TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
        TINYGLTF_COMPONENT_TYPE_SHORT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
        TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT};
    if (!kTypes.count(a.componentType))
        fail(name + " has component type " + std::to_string(a.componentType) +
             ", which glTF does not allow here");
    const int size = tinygltf::GetComponentSizeInBytes(uint32_t(a.componentType));
    if (a.bufferView < 0 || size_t(a.bufferView) >= model.bufferViews.size())
        fail(name + " has no buffer view (bufferView " + std::to_string(a.bufferView) + ")");
    const tinygltf::BufferView& view = model.bufferViews[size_t(a.bufferView)];
    if (view.buffer < 0 || size_t(view.buffer) >= model.buffers.size())
        fail("buffer view " + std::to_string(a.bufferView) + " names buffer " +
             std::to_string(view.buffer) + " of " + std::to_string(model.buffers.size()));
    const size_t bufferBytes = model.buffers[size_t(view.buffer)].data.size();
    const double element = double(size) * components;
    const double stride = view.byteStride ? double(view.byteStride) : element;
    if (stride < element)
        fail("buffer view " + std::to_string(a.bufferView) + " has byteStride " +
             std::to_string(view.byteStride) + ", less than " + name + "'s element of " +
             shortNumber(element) + " bytes");
    const double end = double(a.byteOffset) + stride * (double(a.count) - 1) + element;
    if (a.count == 0 || end > double(view.byteLength) ||
        double(view.byteOffset) + double(view.byteLength) > double(bufferBytes))
        fail(name + ": " + std::to_string(a.count) + " elements from byte " +
             std::to_string(a.byteOffset) + " need " + shortNumber(end) + " bytes of buffer view " +
             std::to_string(a.bufferView) + ", which has " + std::to_string(view.byteLength) +
             " (buffer " + std::to_string(view.buffer) + ": " + std::to_string(bufferBytes) +
             " bytes)");
    return {model.buffers[size_t(view.buffer)].data.data() + view.byteOffset + a.byteOffset,
            size_t(stride), size_t(size)};
}

// An accessor's elements as doubles, every one checked finite.
std::vector<double> readAccessor(const tinygltf::Model& model, int index,
                                 const std::string& attribute, int components, const Fail& fail) {
    const std::string name = accessorName(index, attribute);
    if (index < 0 || size_t(index) >= model.accessors.size())
        fail(attribute + " names accessor " + std::to_string(index) + " of " +
             std::to_string(model.accessors.size()));
    const tinygltf::Accessor& a = model.accessors[size_t(index)];
    if (a.sparse.isSparse) fail(name + " is sparse; pgt reads plain accessors");
    if (tinygltf::GetNumComponentsInType(uint32_t(a.type)) != components)
        fail(name + " has " + std::to_string(tinygltf::GetNumComponentsInType(uint32_t(a.type))) +
             " components; " + attribute + " has " + std::to_string(components));
    const AccessorBytes at = locate(model, a, name, components, fail);
    std::vector<double> out(a.count * size_t(components));
    for (size_t e = 0; e < a.count; ++e) {
        if ((e & 0xffff) == 0) throwIfCancelled();  // Ctrl-C in Python: millions of vertices
        for (size_t c = 0; c < size_t(components); ++c) {
            const double x = component(at.base + at.stride * e + at.componentBytes * c,
                                       a.componentType, a.normalized);
            if (!std::isfinite(x))
                fail(name + " element " + std::to_string(e) + " is not finite (" + shortNumber(x) +
                     ")");
            out[e * size_t(components) + c] = x;
        }
    }
    return out;
}

struct Attributes {
    std::vector<Vec3d> p, n;
    std::vector<Vec2d> uv;
    std::vector<Vec4d> t;  // empty: the asset has no TANGENT
    std::vector<uint32_t> tri;
};

int attribute(const tinygltf::Primitive& prim, const std::string& name) {
    auto it = prim.attributes.find(name);
    return it == prim.attributes.end() ? -1 : it->second;
}

// An attribute's elements, checked to be as many as POSITION's `n` before they are read.
std::vector<double> readAttribute(const tinygltf::Model& model, int acc, const std::string& what,
                                  int components, size_t n, const Fail& fail) {
    if (acc >= 0 && size_t(acc) < model.accessors.size() && model.accessors[size_t(acc)].count != n)
        fail(accessorName(acc, what) + " has " +
             std::to_string(model.accessors[size_t(acc)].count) + " elements; POSITION has " +
             std::to_string(n));
    return readAccessor(model, acc, what, components, fail);
}

// The triangles' vertex indices (0, 1, 2, ... without an index accessor), each below `n`.
std::vector<uint32_t> readIndices(const tinygltf::Model& model, const tinygltf::Primitive& prim,
                                  size_t n, const Fail& fail) {
    std::vector<uint32_t> tri;
    if (prim.indices >= 0) {
        const std::vector<double> idx = readAccessor(model, prim.indices, "indices", 1, fail);
        const int type = model.accessors[size_t(prim.indices)].componentType;
        if (type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
            type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
            type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
            fail(accessorName(prim.indices, "indices") + " has component type " +
                 std::to_string(type) + "; indices are unsigned integers");
        for (size_t k = 0; k < idx.size(); ++k) {
            if (idx[k] >= double(n))
                fail(accessorName(prim.indices, "indices") + " element " + std::to_string(k) +
                     " is index " + std::to_string(int64_t(idx[k])) + "; the primitive has " +
                     std::to_string(n) + " vertices");
            tri.push_back(uint32_t(idx[k]));
        }
    } else {
        for (size_t k = 0; k < n; ++k) tri.push_back(uint32_t(k));
    }
    if (tri.size() % 3 != 0 || tri.empty())
        fail("the primitive has " + std::to_string(tri.size()) +
             (prim.indices >= 0 ? " indices" : " vertices and no indices") +
             ", not a whole number of triangles");
    if (tri.size() / 3 > kMaxGltfTriangles)
        fail("the primitive has " + std::to_string(tri.size() / 3) + " triangles (more than 2^24)");
    return tri;
}

// The primitive's attributes in glTF's own axes and pgt's v; indices checked. Geometry is
// checked before texture coordinates are asked for, so that a broken file says what is broken.
Attributes readAttributes(const tinygltf::Model& model, const tinygltf::Primitive& prim, int uvSet,
                          const Fail& fail) {
    Attributes at;
    const int pos = attribute(prim, "POSITION");
    if (pos < 0) fail("the primitive has no POSITION");
    const std::vector<double> p = readAccessor(model, pos, "POSITION", 3, fail);
    const size_t n = p.size() / 3;
    for (size_t k = 0; k < n; ++k) at.p.push_back({p[3 * k], p[3 * k + 1], p[3 * k + 2]});
    if (const int acc = attribute(prim, "NORMAL"); acc >= 0) {
        const std::vector<double> v = readAttribute(model, acc, "NORMAL", 3, n, fail);
        for (size_t k = 0; k < n; ++k) {
            const Vec3d nk{v[3 * k], v[3 * k + 1], v[3 * k + 2]};
            if (!(glm::length(nk) > 1e-6))
                fail(accessorName(acc, "NORMAL") + " element " + std::to_string(k) +
                     " has length " + shortNumber(glm::length(nk)) + " (a normal is unit)");
            at.n.push_back(glm::normalize(nk));
        }
    }
    if (const int acc = attribute(prim, "TANGENT"); acc >= 0) {
        const std::vector<double> v = readAttribute(model, acc, "TANGENT", 4, n, fail);
        for (size_t k = 0; k < n; ++k) {
            const Vec4d tk{v[4 * k], v[4 * k + 1], v[4 * k + 2], v[4 * k + 3]};
            if (!(glm::length(Vec3d(tk)) > 1e-6) || std::fabs(std::fabs(tk.w) - 1) > 1e-3)
                fail(accessorName(acc, "TANGENT") + " element " + std::to_string(k) + " is (" +
                     shortNumber(tk.x) + ", " + shortNumber(tk.y) + ", " + shortNumber(tk.z) +
                     ", " + shortNumber(tk.w) + "): xyz must not be zero and w +1 or -1");
            at.t.push_back(tk);
        }
    }
    if (!at.n.empty() && !at.t.empty())
        for (size_t k = 0; k < n; ++k)
            if (!(glm::length(glm::cross(at.n[k], glm::normalize(Vec3d(at.t[k])))) > 1e-3))
                fail("TANGENT element " + std::to_string(k) +
                     " is parallel to its NORMAL: no tangent plane");
    at.tri = readIndices(model, prim, n, fail);
    const std::string uvName = "TEXCOORD_" + std::to_string(uvSet);
    const int uvAcc = attribute(prim, uvName);
    if (uvAcc < 0) {
        const std::string what =
            "the primitive has no " + uvName + ": parallax needs texture coordinates";
        uvSet ? fail.at("uv", what) : fail(what);  // the set the scene chose, or the file
    }
    const std::vector<double> uv = readAttribute(model, uvAcc, uvName, 2, n, fail);
    for (size_t k = 0; k < n; ++k)
        at.uv.push_back({uv[2 * k], 1.0 - uv[2 * k + 1]});  // glTF's v runs down the image
    return at;
}

// Without NORMAL, glTF asks for flat normals (every triangle gets its own three vertices) and
// for the asset's tangents to be ignored: MikkTSpace computes them on the flat normals.
void flatNormals(Attributes& at) {
    Attributes flat;
    for (size_t k = 0; k < at.tri.size(); k += 3) {
        const uint32_t* i = &at.tri[k];
        Vec3d n = glm::cross(at.p[i[1]] - at.p[i[0]], at.p[i[2]] - at.p[i[0]]);
        n = glm::length(n) > 0 ? glm::normalize(n) : Vec3d(0, 1, 0);  // glTF's up
        for (int c = 0; c < 3; ++c) {
            flat.tri.push_back(uint32_t(flat.p.size()));
            flat.p.push_back(at.p[i[c]]);
            flat.uv.push_back(at.uv[i[c]]);
            flat.n.push_back(n);
        }
    }
    at = std::move(flat);
}

// The node's local matrix (glTF: column-major `matrix`, else T * R * S).
Mat4d localMatrix(const tinygltf::Node& node) {
    if (node.matrix.size() == 16) {
        Mat4d m;
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r) m[c][r] = node.matrix[size_t(4 * c + r)];
        return m;
    }
    Mat4d m(1.0);
    if (node.translation.size() == 3)
        m = glm::translate(m, Vec3d(node.translation[0], node.translation[1], node.translation[2]));
    if (node.rotation.size() == 4) {
        glm::dquat q(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);
        m = m * glm::mat4_cast(glm::normalize(q));
    }
    if (node.scale.size() == 3)
        m = glm::scale(m, Vec3d(node.scale[0], node.scale[1], node.scale[2]));
    return m;
}

// The world matrix of the node that places the mesh (`node`, checked by selectPrimitive; -1:
// the first node that instances it, set here; none: the identity).
Mat4d worldMatrix(const tinygltf::Model& model, int meshIndex, int& node) {
    const size_t nodes = model.nodes.size();
    std::vector<int> parent(nodes, -1);  // checkNodeGraph made it a forest
    for (size_t k = 0; k < nodes; ++k)
        for (int c : model.nodes[k].children) parent[size_t(c)] = int(k);
    if (node < 0)
        for (size_t k = 0; k < nodes && node < 0; ++k)
            if (model.nodes[k].mesh == meshIndex) node = int(k);
    Mat4d m(1.0);
    for (int k = node; k >= 0; k = parent[size_t(k)]) m = localMatrix(model.nodes[size_t(k)]) * m;
    return m;
}

}  // namespace

namespace {

// The node graph must be a forest: a cycle in "children" is refused wherever it is.
void checkNodeGraph(const tinygltf::Model& model, const Fail& fail) {
    const size_t nodes = model.nodes.size();
    std::vector<int> parent(nodes, -1);
    for (size_t k = 0; k < nodes; ++k)
        for (int c : model.nodes[k].children) {
            if (c < 0 || size_t(c) >= nodes)
                fail("node " + std::to_string(k) + " has child " + std::to_string(c) + " of " +
                     std::to_string(nodes) + " nodes");
            if (parent[size_t(c)] >= 0)
                fail("node " + std::to_string(c) + " has two parents (nodes " +
                     std::to_string(parent[size_t(c)]) + " and " + std::to_string(k) +
                     "): the node graph must be a tree");
            parent[size_t(c)] = int(k);
        }
    std::vector<uint8_t> state(nodes, 0);  // 0 unseen, 1 on the current walk, 2 done
    for (size_t start = 0; start < nodes; ++start) {
        int k = int(start);
        while (k >= 0 && state[size_t(k)] == 0) state[size_t(k)] = 1, k = parent[size_t(k)];
        if (k >= 0 && state[size_t(k)] == 1)
            fail("node " + std::to_string(k) + " is its own ancestor (a cycle in \"children\")");
        for (k = int(start); k >= 0 && state[size_t(k)] == 1; k = parent[size_t(k)])
            state[size_t(k)] = 2;
    }
}

// An index by name among `names` (exactly one must have it), for base.mesh and base.node.
int byName(const std::vector<std::string>& names, const std::string& name, const char* key,
           const Fail& fail) {
    int found = -1, count = 0;
    for (size_t k = 0; k < names.size(); ++k)
        if (names[k] == name) found = found < 0 ? int(k) : found, ++count;
    if (count == 0)
        fail.at(key, std::string("no ") + key + " is named \"" + printable(name, 80) + "\"");
    if (count > 1)
        fail.at(key, std::to_string(count) + (key == std::string("mesh") ? " meshes" : " nodes") +
                         " are named \"" + printable(name, 80) + "\": give the index");
    return found;
}

// The mesh and primitive chosen (a node chosen without a mesh brings its own mesh).
const tinygltf::Primitive& selectPrimitive(const tinygltf::Model& model, GltfSelection& which,
                                           const Fail& fail) {
    std::vector<std::string> names;
    if (!which.nodeName.empty()) {
        for (const auto& n : model.nodes) names.push_back(n.name);
        which.node = byName(names, which.nodeName, "node", fail);
    }
    if (which.node >= 0) {
        if (size_t(which.node) >= model.nodes.size())
            fail.at("node", "node " + std::to_string(which.node) + " of " +
                                std::to_string(model.nodes.size()));
        if (!which.meshGiven) which.mesh = model.nodes[size_t(which.node)].mesh;
        if (model.nodes[size_t(which.node)].mesh != which.mesh)
            fail.at("node", "node " + std::to_string(which.node) + " does not place mesh " +
                                std::to_string(which.mesh));
    }
    if (!which.meshName.empty()) {
        names.clear();
        for (const auto& m : model.meshes) names.push_back(m.name);
        which.mesh = byName(names, which.meshName, "mesh", fail);
    }
    if (model.meshes.empty()) fail("the file has no mesh");
    if (which.mesh < 0 || size_t(which.mesh) >= model.meshes.size())
        fail.at("mesh", "mesh " + std::to_string(which.mesh) + " of " +
                            std::to_string(model.meshes.size()));
    const tinygltf::Mesh& mesh = model.meshes[size_t(which.mesh)];
    if (which.primitive < 0 || size_t(which.primitive) >= mesh.primitives.size())
        fail.at("primitive", "primitive " + std::to_string(which.primitive) + " of mesh " +
                                 std::to_string(which.mesh) + ", which has " +
                                 std::to_string(mesh.primitives.size()));
    const tinygltf::Primitive& prim = mesh.primitives[size_t(which.primitive)];
    if (prim.mode != -1 && prim.mode != TINYGLTF_MODE_TRIANGLES)
        fail("primitive " + std::to_string(which.primitive) + " has mode " +
             std::to_string(prim.mode) + "; pgt reads triangles (mode 4)");
    if (prim.extensions.count("KHR_draco_mesh_compression"))
        fail("the primitive is Draco-compressed; pgt reads uncompressed buffers");
    return prim;
}

// A mesh of several primitives draws one: the scene that did not choose it is told which, on
// stderr (a notice, not an error), with how many there are and how to choose another.
void noteOtherPrimitives(const tinygltf::Model& model, const GltfSelection& which,
                         const Fail& fail) {
    const tinygltf::Mesh& mesh = model.meshes[size_t(which.mesh)];
    if (mesh.primitives.size() < 2) return;
    const size_t dot = fail.field.rfind('.');
    const std::string key = (dot == std::string::npos ? "" : fail.field.substr(0, dot + 1));
    std::fprintf(stderr,
                 "pgt: note: %s: %s = %s: mesh %d%s has %zu primitives; primitive %d is drawn, "
                 "the others are not (%sprimitive chooses one)\n",
                 printable(fail.sceneFile, 480).c_str(), printable(fail.field, 120).c_str(),
                 printable(fail.path, 120).c_str(), which.mesh,
                 mesh.name.empty() ? "" : (" \"" + printable(mesh.name, 60) + "\"").c_str(),
                 mesh.primitives.size(), which.primitive, key.c_str());
}

// MikkTSpace per corner, in the asset's own space: vertices whose corners got different
// frames (a mirror seam) are split.
void mikkTangents(Attributes& at, MikkFrames* stats) {
    const MikkFrames f = mikkTSpace({at.p, at.n, at.uv, at.tri});
    Attributes out;
    std::map<std::tuple<uint32_t, double, double, double, float>, uint32_t> split;
    for (size_t c = 0; c < at.tri.size(); ++c) {
        const uint32_t v = at.tri[c];
        const Vec3d& t = f.tangent[c];
        auto [it, added] =
            split.emplace(std::make_tuple(v, t.x, t.y, t.z, f.sign[c]), uint32_t(out.p.size()));
        if (added) {
            out.p.push_back(at.p[v]);
            out.n.push_back(at.n[v]);
            out.uv.push_back(at.uv[v]);
            out.t.push_back(Vec4d(t, f.sign[c]));
        }
        out.tri.push_back(it->second);
    }
    stats->degenerateUvTriangles = f.degenerateUvTriangles;
    stats->fallbackTangents = f.fallbackTangents;
    at = std::move(out);
}

// glTF's axes to pgt's: +Y up becomes +Z up, a rotation about x (x, y, z) -> (x, -z, y).
const Mat3d kGltfToPgt(Vec3d(1, 0, 0), Vec3d(0, 0, 1), Vec3d(0, -1, 0));  // columns

BaseMesh worldMesh(const Attributes& at, const Mat4d& world, const Fail& fail) {
    const Mat3d a = kGltfToPgt * Mat3d(world);
    const double det = glm::determinant(a);
    if (!(std::fabs(det) > 1e-300) || !std::isfinite(det))
        fail("the node transform is singular (determinant " + std::to_string(det) + ")");
    const Mat3d normalMatrix = glm::transpose(glm::inverse(a));
    const Vec3d move = kGltfToPgt * Vec3d(world[3]);
    const double mirror = det < 0 ? -1.0 : 1.0;
    BaseMesh mesh;
    for (size_t k = 0; k < at.p.size(); ++k) {
        BaseVertex v;
        v.position = a * at.p[k] + move;
        v.uv = at.uv[k];
        v.normal = glm::normalize(normalMatrix * at.n[k]);
        v.tangent = v.bitangent = Vec3d(0);  // without tangents the caller makes the frames
        if (!at.t.empty()) {
            v.tangent = glm::normalize(a * Vec3d(at.t[k]));
            v.handedness = at.t[k].w < 0 ? -mirror : mirror;  // a mirroring node flips w
            v.bitangent = glm::cross(v.normal, v.tangent) * v.handedness;
        }
        if (!allFinite(v.position) || !allFinite(v.normal) || !allFinite(v.tangent))
            fail("vertex " + std::to_string(k) + " is not finite under the node transform");
        mesh.vertices.push_back(v);
    }
    mesh.indices = at.tri;
    if (mirror < 0)  // glTF: a negative determinant turns the front face clockwise
        for (size_t k = 0; k < mesh.indices.size(); k += 3)
            std::swap(mesh.indices[k + 1], mesh.indices[k + 2]);
    return mesh;
}

// The drawn triangles as a cage: positions welded where equal, UVs face-varying.
ControlMesh weldedCage(const BaseMesh& mesh) {
    ControlMesh cage;
    std::map<std::array<double, 3>, int> ids;
    std::vector<int> posOf;
    for (const BaseVertex& v : mesh.vertices) {
        auto [it, added] = ids.emplace(
            std::array<double, 3>{v.position.x + 0.0, v.position.y + 0.0, v.position.z + 0.0},
            int(cage.positions.size()));
        if (added) cage.positions.push_back(v.position);
        posOf.push_back(it->second);
        cage.uvs.push_back(v.uv);
    }
    for (uint32_t i : mesh.indices) {
        cage.faceVerts.push_back(posOf[i]);
        cage.faceUvs.push_back(int(i));
    }
    cage.faceSizes.assign(mesh.indices.size() / 3, 3);
    return cage;
}

}  // namespace

GltfMesh loadGltfMesh(const std::string& path, const GltfSelection& selection, MeshFrames frames,
                      const std::string& sceneFile, const std::string& field) {
    const Fail fail{sceneFile, field, path};
    std::string fileSha1;
    const tinygltf::Model model = readGltfModel(path, selection, frames, fail, &fileSha1);
    checkNodeGraph(model, fail);
    GltfSelection which = selection;
    const tinygltf::Primitive& prim = selectPrimitive(model, which, fail);
    Attributes at = readAttributes(model, prim, which.uvSet, fail);
    if (at.n.empty()) flatNormals(at);
    GltfMesh out;
    MikkFrames stats;
    const bool assetTangents = frames == MeshFrames::Asset && !at.t.empty();
    if (frames == MeshFrames::Pgt)
        at.t.clear();  // Listing 7.4 below makes the frames
    else if (!assetTangents)
        mikkTangents(at, &stats);
    out.drawn.mesh = worldMesh(at, worldMatrix(model, which.mesh, which.node), fail);
    out.framesUsed = assetTangents ? "asset" : "mikktspace";
    if (frames == MeshFrames::Pgt) {
        out.drawn.handedness = computeTangentFrames(out.drawn.mesh, &out.drawn.frames);
        out.framesUsed = "pgt";
    } else {
        out.drawn.frames.degenerateUvTriangles = stats.degenerateUvTriangles;
        out.drawn.frames.fallbackTangents = stats.fallbackTangents;
        for (const BaseVertex& v : out.drawn.mesh.vertices) {
            out.drawn.handedness.push_back(float(v.handedness));
            out.drawn.frames.mirroredVertices += v.handedness < 0;
        }
    }
    out.cage = weldedCage(out.drawn.mesh);
    std::string hashed = fileSha1;  // the file, then every buffer (a .bin beside it)
    for (const auto& b : model.buffers) hashed += OIIO::SHA1::digest(b.data.data(), b.data.size());
    out.cage.sourceSha1 = textSha1(hashed);
    const std::string& name = model.meshes[size_t(which.mesh)].name;
    out.description = "mesh " + std::to_string(which.mesh) +
                      (name.empty() ? "" : " \"" + printable(name, 60) + "\"") + " primitive " +
                      std::to_string(which.primitive) + ", TEXCOORD_" +
                      std::to_string(which.uvSet) + ", " +
                      (which.node >= 0 ? "node " + std::to_string(which.node) : "no node");
    if (!which.primitiveGiven) noteOtherPrimitives(model, which, fail);  // once all is read
    return out;
}

}  // namespace pgt
