// What an engine's vertex stage reads (methods/shader/vertex_stage.h) for a view: the drawn
// base mesh's vertices and the camera's matrices in OpenGL's conventions.
#pragma once

#include "mesh/base_mesh.h"
#include "methods/shader/vertex_stage.h"
#include "scene/camera.h"

namespace pgt {

// The view matrix maps world to eye space (x right, y up, looking down -z); the projection is
// the camera's: a perspective of its vertical field of view and aspect, or an orthographic box
// of its view height; near and far enclose every vertex. The eye of an orthographic camera is
// the point on its axis one unit behind the farthest vertex.
VertexStageInputs vertexStageInputs(const BaseMesh& mesh, const Camera& camera);

}  // namespace pgt
