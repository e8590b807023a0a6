// Box-filtered mipmap chains (heightfield/mipmaps.h).
#include "heightfield/mipmaps.h"

#include <algorithm>
#include <cmath>

namespace pgt {

namespace {

// The source texels destination texel k of n' covers among n, with their overlap weights
// (summing to 1): the interval [k n/n', (k+1) n/n') in source texels.
struct Footprint {
    int first = 0;
    std::vector<double> weights;
};

std::vector<Footprint> footprints(int n, int next) {
    std::vector<Footprint> out(static_cast<size_t>(next));
    const double step = double(n) / double(next);
    for (int k = 0; k < next; ++k) {
        const double a = k * step, b = (k + 1) * step;
        Footprint& f = out[size_t(k)];
        f.first = int(std::floor(a));
        for (int i = f.first; i < n && double(i) < b; ++i)
            f.weights.push_back((std::min(b, double(i + 1)) - std::max(a, double(i))) / step);
    }
    return out;
}

Texture halve(const Texture& src) {
    Texture dst;
    dst.width = std::max(1, src.width / 2);
    dst.height = std::max(1, src.height / 2);
    dst.channels = src.channels;
    dst.address = src.address;
    dst.texels.assign(size_t(dst.width) * dst.height * size_t(dst.channels), 0.0f);
    const auto fx = footprints(src.width, dst.width), fy = footprints(src.height, dst.height);
    for (int j = 0; j < dst.height; ++j)
        for (int i = 0; i < dst.width; ++i)
            for (int c = 0; c < dst.channels; ++c) {
                const Footprint &x = fx[size_t(i)], &y = fy[size_t(j)];
                double sum = 0;
                for (size_t b = 0; b < y.weights.size(); ++b)
                    for (size_t a = 0; a < x.weights.size(); ++a)
                        sum += x.weights[a] * y.weights[b] *
                               src.texel(x.first + int(a), y.first + int(b), c);
                dst.texel(i, j, c) = float(sum);
            }
    return dst;
}

}  // namespace

std::shared_ptr<const std::vector<Texture>> buildMipChain(const Texture& t) {
    auto levels = std::make_shared<std::vector<Texture>>();
    while (true) {
        const Texture& prev = levels->empty() ? t : levels->back();
        if (prev.width == 1 && prev.height == 1) break;
        Texture next = halve(prev);
        levels->push_back(std::move(next));
    }
    return levels;
}

void addMipmaps(Texture& t) {
    if (!t.mips) t.mips = buildMipChain(t);
}

namespace {

void roundTexels(Texture& t, double steps) {
    for (float& h : t.texels)
        h = float(std::nearbyint(std::clamp(double(h), 0.0, 1.0) * steps) / steps);
}

}  // namespace

Texture storedMap(const Texture& t, int bits) {
    const double steps = double((1u << bits) - 1);
    Texture out = t;
    out.mips = nullptr;
    roundTexels(out, steps);
    if (!t.mips) return out;
    auto levels = std::make_shared<std::vector<Texture>>(*buildMipChain(out));
    for (Texture& level : *levels) roundTexels(level, steps);
    out.mips = std::move(levels);
    return out;
}

}  // namespace pgt
