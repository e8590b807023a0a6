// compactFragments and sampleFragments (raster/fragment_list.h).
#include "raster/fragment_list.h"

#include <algorithm>
#include <numeric>
#include <random>

namespace pgt {

FragmentList compactFragments(const Image2D<Fragment>& frags) {
    FragmentList list;
    for (int y = 0; y < frags.height; ++y)
        for (int x = 0; x < frags.width; ++x) {
            const Fragment& f = frags.at(x, y);
            if (!f.covered) continue;
            list.pixel.push_back(y * frags.width + x);
            list.uv0.push_back(f.uv0);
            list.view.push_back(f.viewTangent);
            list.viewExact.push_back(f.viewTangentExact);
            list.uvDx.push_back(f.uvDx);
            list.uvDy.push_back(f.uvDy);
        }
    return list;
}

void FragmentList::append(const FragmentList& from, int32_t pixelOffset) {
    for (int32_t p : from.pixel) pixel.push_back(p + pixelOffset);
    uv0.insert(uv0.end(), from.uv0.begin(), from.uv0.end());
    view.insert(view.end(), from.view.begin(), from.view.end());
    viewExact.insert(viewExact.end(), from.viewExact.begin(), from.viewExact.end());
    uvDx.insert(uvDx.end(), from.uvDx.begin(), from.uvDx.end());
    uvDy.insert(uvDy.end(), from.uvDy.begin(), from.uvDy.end());
}

namespace {
void append(FragmentList& to, const FragmentList& from, size_t k) {
    to.pixel.push_back(from.pixel[k]);
    to.uv0.push_back(from.uv0[k]);
    to.view.push_back(from.view[k]);
    to.viewExact.push_back(from.viewExact[k]);
    to.uvDx.push_back(from.uvDx[k]);
    to.uvDy.push_back(from.uvDy[k]);
}
void assign(FragmentList& to, size_t slot, const FragmentList& from, size_t k) {
    to.pixel[slot] = from.pixel[k];
    to.uv0[slot] = from.uv0[k];
    to.view[slot] = from.view[k];
    to.viewExact[slot] = from.viewExact[k];
    to.uvDx[slot] = from.uvDx[k];
    to.uvDy[slot] = from.uvDy[k];
}
}  // namespace

void FragmentSampler::add(const FragmentList& list) {
    for (size_t k = 0; k < list.size(); ++k, ++seen_) {
        if (count_ <= 0 || seen_ < count_) {
            append(kept_, list, k);
            order_.push_back(seen_);
            continue;
        }
        // Algorithm R: fragment number seen_ replaces a kept one with probability count/(seen+1).
        const int64_t j = std::uniform_int_distribution<int64_t>(0, seen_)(rng_);
        if (j < count_) {
            assign(kept_, size_t(j), list, k);
            order_[size_t(j)] = seen_;
        }
    }
}

FragmentList FragmentSampler::take() {
    std::vector<size_t> idx(order_.size());
    std::iota(idx.begin(), idx.end(), size_t(0));
    std::sort(idx.begin(), idx.end(), [&](size_t a, size_t b) { return order_[a] < order_[b]; });
    FragmentList out;
    for (size_t k : idx) append(out, kept_, k);
    kept_ = {};
    order_.clear();
    return out;
}

FragmentList sampleFragments(const FragmentList& all, int count, uint32_t seed) {
    FragmentSampler sampler(count, seed);
    sampler.add(all);
    return sampler.take();
}

}  // namespace pgt
