// A view's vertex stage inputs and a method's run of its stage (evaluate/vertex_inputs.h).
#include "evaluate/vertex_inputs.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

namespace pgt {

VertexStageInputs vertexStageInputs(const BaseMesh& mesh, const Camera& camera) {
    VertexStageInputs in;
    const size_t n = mesh.vertices.size();
    in.position.reserve(n), in.normal.reserve(n), in.tangent.reserve(n), in.uv.reserve(n);
    in.bitangent.reserve(n);
    double behind = 0;  // how far behind the target the farthest vertex from the eye lies
    for (const BaseVertex& v : mesh.vertices) {
        in.position.emplace_back(v.position);
        in.normal.emplace_back(v.normal);
        in.tangent.emplace_back(Vec3f(v.tangent), v.handedness < 0 ? -1.0f : 1.0f);
        in.bitangent.emplace_back(v.bitangent);
        in.uv.emplace_back(v.uv);
        behind = std::max(behind, glm::dot(v.position - camera.target(), -camera.forward()));
    }
    in.indices = mesh.indices;
    const Vec3d eye =
        camera.isOrthographic() ? camera.target() - camera.forward() * (behind + 1) : camera.eye();
    in.camera = Vec3f(eye);
    double nearest = INFINITY, farthest = 0;  // forward distances from the eye
    for (const BaseVertex& v : mesh.vertices) {
        const double z = glm::dot(v.position - eye, camera.forward());
        nearest = std::min(nearest, z), farthest = std::max(farthest, z);
    }
    const Vec3d r = camera.right(), u = camera.up(), b = -camera.forward();
    glm::dmat4 view(1);
    for (int i = 0; i < 3; ++i) view[i][0] = r[i], view[i][1] = u[i], view[i][2] = b[i];
    view[3] = glm::dvec4(-glm::dot(r, eye), -glm::dot(u, eye), -glm::dot(b, eye), 1);
    in.view = glm::mat4(view);
    const double aspect = double(camera.width()) / camera.height();
    const double lo = std::max(1e-6, 0.5 * nearest), hi = std::max(2 * farthest, 2 * lo);
    if (camera.isOrthographic()) {
        const double h = camera.viewHeight() / 2;
        in.projection = glm::mat4(glm::ortho(-h * aspect, h * aspect, -h, h, lo, hi));
    } else {
        in.projection =
            glm::mat4(glm::perspective(glm::radians(camera.fovDegrees()), aspect, lo, hi));
    }
    return in;
}

bool hasVertexStage(const MethodConfig& cfg) { return cfg.shader() && cfg.shader()->vertexStage(); }

std::optional<VertexOutputs> runMethodVertexStage(const MethodConfig& cfg,
                                                  const VertexStageInputs& in, double scale,
                                                  double bias) {
    if (!hasVertexStage(cfg)) return std::nullopt;
    return runVertexStage(*cfg.shader(), in, scale, bias);
}

}  // namespace pgt
