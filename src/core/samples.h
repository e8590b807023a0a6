// Per-pixel records passed between stages: what the truth saw, what a method produced.
#pragma once

#include <cmath>
#include <cstdint>

#include "core/math.h"

namespace pgt {

struct TruthSample {
    bool hit = false;
    Vec2d uv{0};  // UV of the base point that was displaced to the first hit (docs/model.md §5)
};

struct MethodPixel {
    bool covered = false;  // rasterised and not discarded
    Vec2d uv{NAN};         // uv' (may be non-finite: counted, never averaged)
    uint32_t fetches = 0;
    uint32_t flags = 0;  // MethodFlag bits
};

}  // namespace pgt
