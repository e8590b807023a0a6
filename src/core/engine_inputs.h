// The varyings an engine's vertex stage hands its fragment stage, per fragment: made by the
// rasteriser (raster/raster.h), read by shaders run with "inputs": "engine".
#pragma once

#include "core/math.h"

namespace pgt {

// What an engine's vertex stage hands its fragment stage (docs/methods.md "Engine inputs"), as
// the float varyings a GPU interpolates: the drawn point in world space and its fine screen
// derivatives (the quad's pairs, as Fragment::uvDx, uvDy), the interpolated vertex normal
// and tangent (as interpolated, not renormalised; w the handedness sign) and the camera
// position (orthographic: a point of the pixel's ray at least one world unit in front of the
// drawn point, so that camera - position is the view direction an engine's orthographic path
// has).
struct EngineInputs {
    Vec3f position{0}, positionDx{0}, positionDy{0};
    Vec3f normal{0};
    Vec3f tangent{0};
    float tangentW = 1;
    Vec3f camera{0};
};

}  // namespace pgt
