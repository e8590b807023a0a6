// Built-in cages, OBJ loading (tinyobjloader) and the area-based world scale.
#include "mesh/control_mesh.h"

#include <tiny_obj_loader.h>

#include <cmath>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

#include "core/error.h"
#include "core/json_read.h"

namespace pgt {

ControlMesh makeCubeCage(double size, double tiling) {
    ControlMesh m;
    const double h = size / 2;
    for (int k = 0; k < 8; ++k)
        m.positions.push_back({k & 1 ? h : -h, k & 2 ? h : -h, k & 4 ? h : -h});
    // Faces counter-clockwise seen from outside; each gets its own UV square.
    const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                             {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    const Vec2d corner[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (const auto& f : faces) {
        m.faceSizes.push_back(4);
        for (int c = 0; c < 4; ++c) {
            m.faceVerts.push_back(f[c]);
            m.faceUvs.push_back(int(m.uvs.size()));
            m.uvs.push_back(corner[c] * tiling);
        }
    }
    return m;
}

ControlMesh makeCylinderCage(double radius, double height, int segments, double tilingU,
                             double tilingV) {
    ControlMesh m;
    for (int ring = 0; ring < 2; ++ring)
        for (int i = 0; i < segments; ++i) {
            double a = 2 * kPi * i / segments;
            m.positions.push_back(
                {radius * std::cos(a), radius * std::sin(a), (ring - 0.5) * height});
        }
    // UV columns 0..segments: column `segments` duplicates column 0 at u = tilingU (the seam).
    for (int ring = 0; ring < 2; ++ring)
        for (int i = 0; i <= segments; ++i)
            m.uvs.push_back({tilingU * i / segments, tilingV * ring});
    for (int i = 0; i < segments; ++i) {
        int a = i, b = (i + 1) % segments;
        m.faceSizes.push_back(4);
        m.faceVerts.insert(m.faceVerts.end(), {a, b, segments + b, segments + a});
        int ua = i, ub = i + 1, row = segments + 1;
        m.faceUvs.insert(m.faceUvs.end(), {ua, ub, row + ub, row + ua});
    }
    return m;
}

ControlMesh makeTorusCage(double majorRadius, double minorRadius, int segU, int segV,
                          double tilingU, double tilingV) {
    ControlMesh m;
    for (int j = 0; j < segV; ++j)
        for (int i = 0; i < segU; ++i) {
            double a = 2 * kPi * i / segU, b = 2 * kPi * j / segV;
            double rr = majorRadius + minorRadius * std::cos(b);
            m.positions.push_back({rr * std::cos(a), rr * std::sin(a), minorRadius * std::sin(b)});
        }
    for (int j = 0; j <= segV; ++j)
        for (int i = 0; i <= segU; ++i) m.uvs.push_back({tilingU * i / segU, tilingV * j / segV});
    for (int j = 0; j < segV; ++j)
        for (int i = 0; i < segU; ++i) {
            int i1 = (i + 1) % segU, j1 = (j + 1) % segV;
            m.faceSizes.push_back(4);
            m.faceVerts.insert(m.faceVerts.end(),
                               {j * segU + i, j * segU + i1, j1 * segU + i1, j1 * segU + i});
            int row = segU + 1;
            m.faceUvs.insert(m.faceUvs.end(), {j * row + i, j * row + i + 1, (j + 1) * row + i + 1,
                                               (j + 1) * row + i});
        }
    return m;
}

namespace {

// tinyobjloader reads a coordinate it cannot parse ("nan", "inf", "1e999") as 0 without a
// word; pgt refuses it, naming the line. Only "v" and "vt" records feed the mesh.
void checkObjNumbers(const std::string& text, const std::string& path, const std::string& sceneFile,
                     const std::string& field) {
    size_t lineNo = 0;
    for (size_t pos = 0; pos < text.size();) {
        size_t end = text.find('\n', pos);
        if (end == std::string::npos) end = text.size();
        std::string line = text.substr(pos, end - pos);
        pos = end + 1;
        ++lineNo;
        std::istringstream words(line);
        std::string tag, word;
        words >> tag;
        if (tag != "v" && tag != "vt") continue;
        while (words >> word) {
            if (word[0] == '#') break;
            char* stop = nullptr;
            double x = std::strtod(word.c_str(), &stop);
            if (*stop != '\0' || !std::isfinite(x))
                throw InputError(sceneFile, field, path + " line " + std::to_string(lineNo),
                                 "\"" + tag + "\" has a coordinate that is not a finite number: " +
                                     word.substr(0, 40));
        }
    }
}

}  // namespace

ControlMesh loadObjMesh(const std::string& path, const std::string& sceneFile,
                        const std::string& field) {
    // An OBJ of 2^20 quads (the cage limit) is about 100 MB of text; 1 GiB bounds the read.
    const std::string text =
        readTextFile(path, sceneFile, field, "OBJ file", std::uintmax_t(1) << 30);
    checkObjNumbers(text, path, sceneFile, field);
    tinyobj::ObjReaderConfig config;
    config.triangulate = false;  // keep quads: the subdivision schemes want the cage as drawn
    tinyobj::ObjReader reader;
    if (!reader.ParseFromString(text, "", config))
        throw InputError(sceneFile, field, path, "cannot read OBJ: " + reader.Error());
    const auto& attrib = reader.GetAttrib();
    ControlMesh m;
    m.sourceSha1 = textSha1(text);  // the study identity's record of this file
    for (size_t k = 0; k + 2 < attrib.vertices.size(); k += 3)
        m.positions.push_back({attrib.vertices[k], attrib.vertices[k + 1], attrib.vertices[k + 2]});
    for (size_t k = 0; k + 1 < attrib.texcoords.size(); k += 2)
        m.uvs.push_back({attrib.texcoords[k], attrib.texcoords[k + 1]});
    // Every face corner must name an existing position and texture coordinate: OpenSubdiv
    // and the UV lookups index with them unchecked. Relative (negative) indices were already
    // resolved by tinyobjloader and are out of range here if they pointed before the start.
    auto checkIndex = [&](int index, size_t count, const char* what, size_t face,
                          const std::string& shape) {
        if (index < 0 || size_t(index) >= count)
            throw InputError(sceneFile, field, path,
                             "face " + std::to_string(face) + " of shape \"" + shape +
                                 "\" refers to " + what + " " + std::to_string(index + 1) + " of " +
                                 std::to_string(count) + " (OBJ counts from 1)");
    };
    for (const auto& shape : reader.GetShapes()) {
        size_t offset = 0;
        for (size_t f = 0; f < shape.mesh.num_face_vertices.size(); ++f) {
            int n = shape.mesh.num_face_vertices[f];
            if (n < 3)
                throw InputError(sceneFile, field, path,
                                 "face " + std::to_string(f) + " has fewer than 3 vertices");
            m.faceSizes.push_back(n);
            for (int c = 0; c < n; ++c) {
                const auto& idx = shape.mesh.indices[offset + size_t(c)];
                if (idx.texcoord_index == -1)
                    throw InputError(sceneFile, field, path,
                                     "face " + std::to_string(f) + " of shape \"" + shape.name +
                                         "\" has no texture coordinates (vt)");
                checkIndex(idx.vertex_index, m.positions.size(), "vertex", f, shape.name);
                checkIndex(idx.texcoord_index, m.uvs.size(), "texture coordinate", f, shape.name);
                m.faceVerts.push_back(idx.vertex_index);
                m.faceUvs.push_back(idx.texcoord_index);
            }
            offset += size_t(n);
        }
    }
    if (m.faceSizes.empty()) throw InputError(sceneFile, field, path, "the OBJ has no faces");
    for (const auto& p : m.positions)
        if (!allFinite(p)) throw InputError(sceneFile, field, path, "non-finite vertex position");
    for (const auto& t : m.uvs)
        if (!allFinite(t))
            throw InputError(sceneFile, field, path, "non-finite texture coordinate");
    return m;
}

double worldPerUvFromAreas(const ControlMesh& mesh) {
    double world = 0, uv = 0;
    size_t corner = 0;
    for (int n : mesh.faceSizes) {
        for (int k = 1; k + 1 < n; ++k) {
            Vec3d p0 = mesh.positions[mesh.faceVerts[corner]];
            Vec3d p1 = mesh.positions[mesh.faceVerts[corner + k]];
            Vec3d p2 = mesh.positions[mesh.faceVerts[corner + k + 1]];
            Vec2d t0 = mesh.uvs[mesh.faceUvs[corner]], t1 = mesh.uvs[mesh.faceUvs[corner + k]];
            Vec2d t2 = mesh.uvs[mesh.faceUvs[corner + k + 1]];
            world += glm::length(glm::cross(p1 - p0, p2 - p0)) / 2;
            Vec2d a = t1 - t0, b = t2 - t0;
            uv += std::fabs(a.x * b.y - a.y * b.x) / 2;
        }
        corner += size_t(n);
    }
    if (!(uv > 0)) throw std::invalid_argument("the mesh's UV area is zero");
    return std::sqrt(world / uv);
}

}  // namespace pgt
