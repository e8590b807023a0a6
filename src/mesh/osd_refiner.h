// The one place a ControlMesh becomes an OpenSubdiv TopologyRefiner: the drawn mesh
// (mesh/refine.cpp) and the truth's tessellations (truth/truth.cpp) must agree on scheme and
// boundary/face-varying options, so they share this.
#pragma once

#include <opensubdiv/far/topologyRefiner.h>

#include <memory>

#include "mesh/control_mesh.h"
#include "mesh/refine.h"

namespace pgt {

// Edge-and-corner vertex boundaries; face-varying UVs interpolated linearly everywhere.
// Throws std::invalid_argument when OpenSubdiv rejects the topology or Loop gets non-triangles.
std::unique_ptr<OpenSubdiv::Far::TopologyRefiner> createRefiner(const ControlMesh& cage,
                                                                Scheme scheme);

}  // namespace pgt
