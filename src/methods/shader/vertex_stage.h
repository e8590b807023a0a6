// An engine's own vertex shader run as it ships (GlslSpec::VertexStage; docs/methods.md "The
// engine's vertex stage"): OpenGL runs it once on every vertex of the drawn base mesh and
// transform feedback captures the outputs the fragment code reads; each fragment's value is
// then its triangle's three interpolated at the fragment's perspective-correct barycentrics
// (raster/raster.h FragmentInputs::bary), as a GPU interpolates varyings.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/math.h"
#include "methods/shader/glsl_spec.h"

namespace pgt {

// What the stage reads: the drawn mesh (world space, pgt's +z up; tangent w the handedness
// sign) and the view's matrices in OpenGL's conventions (eye space looks down -z; clip space as
// a perspective or orthographic projection makes it), the model matrix the identity (pgt's
// mesh is in world space), and the eye (orthographic: a point behind every vertex on the
// view's axis).
struct VertexStageInputs {
    std::vector<Vec3f> position, normal, bitangent;
    std::vector<glm::vec4> tangent;
    std::vector<Vec2f> uv;
    std::vector<uint32_t> indices;  // triangles, as Fragment::triangle counts them
    glm::mat4 view{1}, projection{1};
    Vec3f camera{0};
};

// The captured outputs: per vertex `stride` floats, each link's (GlslSpec::VertexStage::links,
// in order; a matrix's columns one link each) from its `offset`; the mesh's indices beside
// them.
struct VertexOutputs {
    int stride = 0;
    std::vector<int> offset, components;
    std::vector<float> values;
    std::vector<uint32_t> indices;
    // Link l at barycentrics `bary` of triangle t (components past the link's are 0).
    glm::vec4 at(uint32_t t, const Vec3d& bary, size_t l) const;
};

// The names of pgt's vertex data ("attributes": position, normal, tangent, bitangent, uv) and
// of the camera's matrices ("matrices": model, view, ..., camera_position), from the tables
// that bind them.
const std::vector<std::string>& vertexAttributeNames();
const std::vector<std::string>& vertexMatrixNames();

// Runs the spec's vertex stage over `in` with the case's (s, b) for uniforms bound to them.
// Throws InputError naming the vertex file for a compile or link error, an attribute or
// matrix that is not active in it, or a uniform active in neither stage.
VertexOutputs runVertexStage(const GlslSpec& spec, const VertexStageInputs& in, double scale,
                             double bias);

}  // namespace pgt
