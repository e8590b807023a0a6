// An engine's vertex stage for the frame (the one door above evaluate/ to
// methods/shader/vertex_stage.h): what it reads for a view (the drawn base mesh's vertices and
// the camera's matrices in OpenGL's conventions) and a method's run of it.
#pragma once

#include <optional>

#include "mesh/base_mesh.h"
#include "methods/method.h"
#include "methods/shader/vertex_stage.h"
#include "scene/camera.h"

namespace pgt {

// The view matrix maps world to eye space (x right, y up, looking down -z); the projection is
// the camera's: a perspective of its vertical field of view and aspect, or an orthographic box
// of its view height; near and far enclose every vertex. The eye of an orthographic camera is
// the point on its axis one unit behind the farthest vertex.
VertexStageInputs vertexStageInputs(const BaseMesh& mesh, const Camera& camera);

// Whether `cfg` has an engine vertex stage (its shader entry's "vertex").
bool hasVertexStage(const MethodConfig& cfg);
// The outputs of `cfg`'s vertex stage over a view's inputs (vertexStageInputs) at (s, b); none
// where it has no vertex stage.
std::optional<VertexOutputs> runMethodVertexStage(const MethodConfig& cfg,
                                                  const VertexStageInputs& in, double scale,
                                                  double bias);

}  // namespace pgt
