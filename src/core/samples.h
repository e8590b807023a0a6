// Per-pixel records passed between stages: what the truth saw, what a method produced.
#pragma once

#include <cmath>
#include <cstdint>

#include "core/math.h"

namespace pgt {

// A pixel's shadow state against the view's light (docs/model.md §5b): none without a light
// (or without a hit), else lit or in shadow.
enum ShadowState : int8_t { kShadowNone = -1, kShadowLit = 0, kShadowDark = 1 };

struct TruthSample {
    bool hit = false;
    int8_t shadow = kShadowNone;  // the hit toward the view's light (docs/model.md §5b)
    // A miss where the sheet must be hit: a plane's ray that crossed the relief's whole slab
    // over the built sheet (a hole between primitives; docs/model.md §5). Counted, never hidden.
    bool hole = false;
    Vec2d uv{0};     // UV of the base point that was displaced to the first hit (docs/model.md §5)
    double t = NAN;  // the hit's distance along the pixel's ray (world units)
    // Depth offset (docs/model.md §5b): the hit's distance along the ray beyond the drawn base
    // surface's point, in UV units; the pipeline sets it where the rasteriser covers the pixel.
    double depth = NAN;
};

struct MethodPixel {
    bool covered = false;         // rasterised and not discarded
    int8_t shadow = kShadowNone;  // its shadow march's answer (none: no light or no march)
    float depth = NAN;  // its depth offset along the eye ray, UV units (docs/model.md §6c)
    Vec2d uv{NAN};      // uv' (may be non-finite: counted, never averaged)
    uint32_t fetches = 0;
    uint32_t flags = 0;  // MethodFlag bits
};

}  // namespace pgt
