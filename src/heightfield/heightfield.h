// Height fields (docs/model.md §1): loading any OpenImageIO format, procedural generators, and
// the normal and parallax maps derived from a height field for Lengyel FGED 2's methods.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "heightfield/texture.h"

namespace pgt {

// Loads one channel of an image as h in [0,1] (8-bit / 255, 16-bit / 65535, float as is),
// flipped so that row 0 is the bottom of the picture. Throws InputError naming `file` and
// `field` for unreadable files, a bad channel, or a non-finite texel (with its position).
Texture loadHeightImage(const std::string& path, int channel, const std::string& sceneFile,
                        const std::string& field, bool channelGiven);

// The image's header only (no pixels decoded): size and channel count, after the same
// checks as loadHeightImage (a regular file, a readable header, the size limits, the
// channel, the memory its decoding needs). Lets a scene refuse a huge map before decoding.
struct HeightImageHeader {
    int width = 0, height = 0, channels = 0;
};
HeightImageHeader probeHeightImage(const std::string& path, int channel,
                                   const std::string& sceneFile, const std::string& field);

// Procedural height maps. `params` holds the generator's own fields (validated here);
// `field` is the JSON path used in error messages.
Texture makeProceduralHeight(const nlohmann::json& params, const std::string& sceneFile,
                             const std::string& field);

// Lengyel FGED 2 Eq. 7.41-7.43 as docs/model.md §6b pins them down: per texel
// d_x = s*W/2 * (h[i+1,j] - h[i-1,j]), d_y = s*H/2 * (h[i,j+1] - h[i,j-1]),
// m = normalise(-d_x, -d_y, 1) (3 channels) and parallax P = m_z * (s*h + b) (1 channel).
struct DerivedMaps {
    Texture normal;    // m, 3 channels, unit length per texel
    Texture parallax;  // m_z * (s*h + b), UV units
};
DerivedMaps makeDerivedMaps(const Texture& height, double scaleUv, double biasUv);

}  // namespace pgt
