// Mipmap chains (scene "heightmap": {"mipmaps": true}): the box-filtered levels a GPU's
// glGenerateMipmap makes, built once here and uploaded level by level to the GL, so that the
// C++ methods (sampleTrilinear) and the GLSL methods read the same levels.
#pragma once

#include <memory>
#include <vector>

#include "heightfield/texture.h"

namespace pgt {

// Levels 1..q of `t` (every channel): level k is max(1, floor(W / 2^k)) x max(1, floor(H /
// 2^k)) texels, each the area-weighted mean of the level above it over its footprint (the
// 2x2 mean on even sides; odd sides weigh the straddled texel by its overlap). q is the level
// where both sides reach 1. Level k keeps t's address mode.
std::shared_ptr<const std::vector<Texture>> buildMipChain(const Texture& t);

// `t` with its chain (a no-op when it has one).
void addMipmaps(Texture& t);

// The map as a normalised `bits`-bit texture stores it (an engine's unorm8 or unorm16 upload):
// each texel clamped to [0, 1] and rounded to the nearest k / (2^bits - 1) (ties to even), and
// where `t` has mipmaps, levels made from the rounded level 0 and rounded again, as an engine
// builds them from what it uploaded.
Texture storedMap(const Texture& t, int bits);

}  // namespace pgt
