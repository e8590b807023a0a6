// The maps a method reads, one kind each: the height map and what pgt precomputes from it.
// Every place that holds, builds, binds, checks, estimates or names maps loops over this one
// list (docs/layout.md "A new map"): the method table says which kinds a built-in reads, a
// GLSL method reads the kinds whose samplers it names, the method-texture cache
// (evaluate/evaluate.h) builds them, methods/shader/glsl_method.cpp binds them.
#pragma once

#include <array>
#include <bitset>

#include "heightfield/texture.h"

namespace pgt {

struct MinMaxPyramid;  // heightfield/minmax_pyramid.h: maxmip's tree over the height map
struct ConeMap;        // heightfield/cone_map.h: cone's ratios per cell

enum class MapKind { Height, Normal, Parallax, Pyramid, Cone, RelaxedCone };
inline constexpr size_t kMapKinds = 6;

struct MapKindInfo {
    MapKind kind;
    const char* name;         // "cone"
    const char* samplerKey;   // a GLSL method entry's key naming its sampler: "cone_sampler"
    const char* twinSampler;  // the sampler's name in the built-ins' GLSL twins: "coneMap"
    int glUnit;               // the texture unit a GLSL method reads it from
    // Built for each (s, b) it is read at (Lengyel FGED 2's derived maps), not once per height map
    // (and sign of s) as the precomputed ones.
    bool perDisplacement;
    // Bytes per texel of the height map it holds, with its build's peak (measured at 2048^2;
    // docs/performance.md), and the GL's copy of it (4 bytes a channel).
    double bytesPerTexel;
    int glChannels;
};

// In MapKind order.
inline constexpr std::array<MapKindInfo, kMapKinds> kMapKindTable = {{
    {MapKind::Height, "height", "sampler", "heightMap", 0, false, 0, 1},
    {MapKind::Normal, "normal", "normal_sampler", "normalMap", 3, true, 12, 3},
    {MapKind::Parallax, "parallax", "parallax_sampler", "parallaxMap", 4, true, 4, 1},
    {MapKind::Pyramid, "pyramid", "pyramid_sampler", "pyramidMap", 5, false, 32.0 / 3.0, 2},
    {MapKind::Cone, "cone", "cone_sampler", "coneMap", 6, false, 48, 1},
    // 8 measured, and the float copy of the map its build walks (4, with a border).
    {MapKind::RelaxedCone, "relaxed_cone", "relaxed_cone_sampler", "relaxedConeMap", 7, false, 12,
     1},
}};

// A set of map kinds: what a configuration reads.
class MapSet {
  public:
    MapSet() = default;
    MapSet(std::initializer_list<MapKind> kinds) {
        for (MapKind k : kinds) add(k);
    }
    bool has(MapKind k) const { return bits_.test(size_t(k)); }
    void add(MapKind k) { bits_.set(size_t(k)); }
    MapSet& operator|=(const MapSet& o) {
        bits_ |= o.bits_;
        return *this;
    }

  private:
    std::bitset<kMapKinds> bits_;
};

// One (s, b)'s maps by kind, each null until built: what MethodContext samples and a GL draw
// binds.
struct MapRefs {
    const Texture* height = nullptr;  // h
    const Texture* normal =
        nullptr;  // Lengyel FGED 2's unit normal m, RGB (tangent_plane, iterative_slope)
    const Texture* parallax = nullptr;       // m_z * (s*h + b)
    const MinMaxPyramid* pyramid = nullptr;  // maxmip
    const ConeMap* cone = nullptr;           // cone: the map for the sign of s
    const ConeMap* relaxedCone = nullptr;    // relaxed_cone: the same, relaxed
    bool has(MapKind k) const {
        switch (k) {
            case MapKind::Height:
                return height;
            case MapKind::Normal:
                return normal;
            case MapKind::Parallax:
                return parallax;
            case MapKind::Pyramid:
                return pyramid;
            case MapKind::Cone:
                return cone;
            case MapKind::RelaxedCone:
                return relaxedCone;
        }
        return false;
    }
};

}  // namespace pgt
