// Textures and the one bilinear sampler (docs/model.md §1) used by the truth and by every method.
// Texel (i, j) is column i, row j counted from the BOTTOM; its centre is at
// ((i + 0.5) / W, (j + 0.5) / H). Sampling is templated on the scalar so that methods run in
// float (as a GPU does) and the truth in double, with the same arithmetic.
#pragma once

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "core/math.h"

namespace pgt {

enum class Address { Repeat, Clamp };

std::string toString(Address a);

struct Texture {
    int width = 0;
    int height = 0;
    int channels = 1;
    Address address = Address::Repeat;
    std::vector<float> texels;  // (j * width + i) * channels + c, j from the bottom
    // Levels 1..q of a box-filtered mipmap chain (heightfield/mipmaps.h), shared by copies;
    // null without mipmaps. Level 0 is this texture.
    std::shared_ptr<const std::vector<Texture>> mips;

    float texel(int i, int j, int c = 0) const {
        return texels[(size_t(j) * width + i) * channels + c];
    }
    float& texel(int i, int j, int c = 0) { return texels[(size_t(j) * width + i) * channels + c]; }
};

namespace detail {

// Integer texel index of a continuous texel coordinate x (texel units, centres at k + 0.5
// already subtracted). Returns the two neighbours and the fraction. Non-finite or huge
// coordinates are reduced first so that the integer conversion is always defined.
template <class Real>
[[gnu::always_inline]] inline void texelPair(Real x, int n, Address address, int& i0, int& i1,
                                             Real& f) {
    Real fl = std::floor(x);
    f = x - fl;
    // Beyond 2^30 texels the float position has no fractional precision left; reduce so
    // that the int conversion below is defined (callers count non-finite inputs separately).
    if (!(std::fabs(fl) < Real(1 << 30))) {
        fl = std::isfinite(fl) ? std::fmod(fl, Real(n)) : Real(0);
        if (!std::isfinite(f)) f = Real(0);
    }
    long k = long(fl);
    if (address == Address::Repeat) {
        // Inside the first period (the common case) no division is needed.
        long m = k;
        if (m < 0 || m >= n) {
            m = k % n;
            if (m < 0) m += n;
        }
        i0 = int(m);
        i1 = (i0 + 1 == n) ? 0 : i0 + 1;
    } else {
        i0 = int(k < 0 ? 0 : (k >= n ? n - 1 : k));
        long k1 = k + 1;
        i1 = int(k1 < 0 ? 0 : (k1 >= n ? n - 1 : k1));
    }
}

}  // namespace detail

// The fraction of 8 fractional bits a GPU's bilinear filter weighs with: NVIDIA documents its
// weights as 9-bit fixed point with 8 fractional bits (CUDA C Programming Guide, "Linear
// Filtering"); AMD's are the same width. Rounded to nearest here (the rounding is not
// documented).
template <class Real>
inline Real gpu8Fraction(Real f) {
    return std::floor(f * Real(256) + Real(0.5)) / Real(256);
}

// Bilinear interpolation of texel centres (docs/model.md §1) of channel c; NaN in, NaN out.
// gpu8: the weights' fractions rounded to 8 bits as a GPU's filter does (gpu8Fraction); a
// flag, not a second copy of the sampler, so that the methods' loops stay as small as they
// were (BM_Method: two inlined copies cost pom and relief 10-25 %).
// (Always inlined: the methods' marches are a loop around it; measured in BM_Method.)
template <class Real>
[[gnu::always_inline]] inline Real sampleBilinear(const Texture& t, Vec2<Real> uv, int c = 0,
                                                  bool gpu8 = false) {
    if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) return Real(NAN);
    Real x = uv.x * Real(t.width) - Real(0.5);
    Real y = uv.y * Real(t.height) - Real(0.5);
    int i0, i1, j0, j1;
    Real fx, fy;
    detail::texelPair(x, t.width, t.address, i0, i1, fx);
    detail::texelPair(y, t.height, t.address, j0, j1, fy);
    if (gpu8) {
        fx = gpu8Fraction(fx);
        fy = gpu8Fraction(fy);
    }
    Real a = Real(t.texel(i0, j0, c)), b = Real(t.texel(i1, j0, c));
    Real d = Real(t.texel(i0, j1, c)), e = Real(t.texel(i1, j1, c));
    Real bottom = a + (b - a) * fx;
    Real top = d + (e - d) * fx;
    return bottom + (top - bottom) * fy;
}

// The level of detail lambda of the GL specification (4.6 §8.14.1, eq. 8.6-8.7, no bias or
// clamps) for a map of W x H texels and the UV derivatives along screen x and y:
// rho = max(|d(u W, v H)/dx|, |d(u W, v H)/dy|), lambda = log2(rho). Non-finite derivatives
// (a helper pixel beyond a pinhole's horizon) give +infinity: the coarsest level.
template <class Real>
inline Real lodFromGradients(Vec2<Real> dx, Vec2<Real> dy, int width, int height) {
    const Real w = Real(width), h = Real(height);
    const Real rx = std::hypot(dx.x * w, dx.y * h), ry = std::hypot(dy.x * w, dy.y * h);
    const Real rho = std::max(rx, ry);
    if (!std::isfinite(rho)) return Real(INFINITY);
    return std::log2(rho);  // rho = 0 (a constant uv): -infinity, level 0
}

// Trilinear filtering (GL_LINEAR_MIPMAP_LINEAR, GL 4.6 §8.14.2-3) of channel c at level of
// detail `lod`: level 0 bilinear when lod <= 0 (magnification) or the map has no mipmaps;
// levels floor(lod) and floor(lod) + 1 mixed by fract(lod); the last level beyond it.
template <class Real>
inline Real sampleTrilinear(const Texture& t, Vec2<Real> uv, Real lod, int c = 0,
                            bool gpu8 = false) {
    if (!(lod > Real(0)) || !t.mips || t.mips->empty()) return sampleBilinear<Real>(t, uv, c, gpu8);
    const auto& levels = *t.mips;
    const Real q = Real(levels.size());
    if (lod >= q) return sampleBilinear<Real>(levels.back(), uv, c, gpu8);
    const int d1 = int(std::floor(lod));
    const Real f = lod - Real(d1);
    const Texture& t1 = d1 == 0 ? t : levels[size_t(d1 - 1)];
    const Real a = sampleBilinear<Real>(t1, uv, c, gpu8);
    const Real b = sampleBilinear<Real>(levels[size_t(d1)], uv, c, gpu8);
    return (Real(1) - f) * a + f * b;
}

}  // namespace pgt
