// compactFragments and sampleFragments (raster/fragment_list.h).
#include "raster/fragment_list.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <numeric>
#include <random>

namespace pgt {

FragmentList compactFragments(const Image2D<Fragment>& frags, const Image2D<FragmentInputs>* inputs,
                              std::vector<HelperLane>* helpers) {
    FragmentList list;
    RasterOptions all;
    all.light = Vec3d(1);  // kept whatever the view's light
    compactFragments(frags, inputs, all, list, helpers);
    return list;
}

void compactFragments(const Image2D<Fragment>& frags, const Image2D<FragmentInputs>* inputs,
                      const RasterOptions& made, FragmentList& list,
                      std::vector<HelperLane>* helpers) {
    const bool lights = made.light != Vec3d(0), exact = made.exactFrame,
               derivatives = made.uvDerivatives;
    if (inputs && inputs->data.size() != frags.data.size()) inputs = nullptr;  // not made
    // Rows counted, then filled at their offsets, over all cores.
    const int W = frags.width, H = frags.height;
    std::vector<size_t> start(size_t(H) + 1, 0);
    tbb::parallel_for(0, H, [&](int y) {
        size_t n = 0;
        for (int x = 0; x < W; ++x) n += frags.at(x, y).covered;
        start[size_t(y) + 1] = n;
    });
    std::partial_sum(start.begin(), start.end(), start.begin());
    const size_t total = start.back();
    list.pixel.resize(total);
    list.uv0.resize(total);
    list.view.resize(total);
    list.viewExact.resize(exact ? total : 0);
    list.uvDx.resize(derivatives ? total : 0);
    list.uvDy.resize(derivatives ? total : 0);
    list.light.resize(lights ? total : 0);
    list.lightExact.resize(lights ? total : 0);
    list.viewVertex.resize(inputs ? total : 0);
    list.engine.resize(inputs ? total : 0);
    list.bary.resize(inputs ? total : 0);
    list.triangle.resize(helpers ? total : 0);
    list.helpers.clear();
    if (helpers) list.helpers.swap(*helpers);
    tbb::parallel_for(0, H, [&](int y) {
        size_t k = start[size_t(y)];
        for (int x = 0; x < W; ++x) {
            const Fragment& f = frags.at(x, y);
            if (!f.covered) continue;
            list.pixel[k] = y * W + x;
            list.uv0[k] = f.uv0;
            list.view[k] = f.viewTangent;
            if (exact) list.viewExact[k] = f.viewTangentExact;
            if (derivatives) list.uvDx[k] = f.uvDx, list.uvDy[k] = f.uvDy;
            if (lights) {
                list.light[k] = f.lightTangent;
                list.lightExact[k] = f.lightTangentExact;
            }
            if (inputs) {
                list.viewVertex[k] = inputs->at(x, y).viewVertex;
                list.engine[k] = inputs->at(x, y).engine;
                list.bary[k] = inputs->at(x, y).bary;
            }
            if (helpers) list.triangle[k] = f.triangle;
            ++k;
        }
    });
}

void FragmentList::append(const FragmentList& from, int32_t pixelOffset) {
    // The optional lists stay empty unless either side has them; then this side's are filled
    // first as viewVertexAt and engineAt read them.
    const size_t before = size();
    const bool vertex = !viewVertex.empty() || !from.viewVertex.empty();
    const bool inputs = !engine.empty() || !from.engine.empty();
    // Derivatives only where both sides have them (else none: zero, as the raster leaves them).
    const bool derivatives = (before == 0 || hasDerivatives()) && from.hasDerivatives();
    for (size_t k = viewVertex.size(); vertex && k < before; ++k) viewVertex.push_back(view[k]);
    for (size_t k = viewExact.size(); k < before; ++k) viewExact.push_back(view[k]);
    light.resize(before, Vec3d(0)), lightExact.resize(before, Vec3d(0));  // none: zero
    if (inputs) engine.resize(before);
    if (!derivatives) uvDx.clear(), uvDy.clear();
    for (int32_t p : from.pixel) pixel.push_back(p + pixelOffset);
    uv0.insert(uv0.end(), from.uv0.begin(), from.uv0.end());
    view.insert(view.end(), from.view.begin(), from.view.end());
    if (derivatives) {
        uvDx.insert(uvDx.end(), from.uvDx.begin(), from.uvDx.end());
        uvDy.insert(uvDy.end(), from.uvDy.begin(), from.uvDy.end());
    }
    for (size_t k = 0; k < from.size(); ++k) {
        viewExact.push_back(from.viewExactAt(k));
        light.push_back(from.lightAt(k));
        lightExact.push_back(from.lightAt(k, true));
        if (vertex) viewVertex.push_back(from.viewVertexAt(k));
        if (inputs) engine.push_back(from.engineAt(k));
    }
}

namespace {
void append(FragmentList& to, const FragmentList& from, size_t k) {
    to.pixel.push_back(from.pixel[k]);
    to.uv0.push_back(from.uv0[k]);
    to.view.push_back(from.view[k]);
    to.viewExact.push_back(from.viewExactAt(k));
    if (from.hasDerivatives()) to.uvDx.push_back(from.uvDx[k]), to.uvDy.push_back(from.uvDy[k]);
    to.light.push_back(from.lightAt(k));
    to.lightExact.push_back(from.lightAt(k, true));
    if (!from.viewVertex.empty()) to.viewVertex.push_back(from.viewVertexAt(k));
    if (!from.engine.empty()) to.engine.push_back(from.engineAt(k));
    // A vertex stage's outputs are read at the triangle's barycentrics (timing them too).
    if (from.bary.size() == from.size() && from.triangle.size() == from.size()) {
        to.bary.push_back(from.bary[k]);
        to.triangle.push_back(from.triangle[k]);
    }
}
void assign(FragmentList& to, size_t slot, const FragmentList& from, size_t k) {
    to.pixel[slot] = from.pixel[k];
    to.uv0[slot] = from.uv0[k];
    to.view[slot] = from.view[k];
    to.viewExact[slot] = from.viewExactAt(k);
    if (from.hasDerivatives() && slot < to.uvDx.size())
        to.uvDx[slot] = from.uvDx[k], to.uvDy[slot] = from.uvDy[k];
    to.light[slot] = from.lightAt(k);
    to.lightExact[slot] = from.lightAt(k, true);
    if (!from.viewVertex.empty()) to.viewVertex[slot] = from.viewVertexAt(k);
    if (!from.engine.empty()) to.engine[slot] = from.engineAt(k);
    if (from.bary.size() == from.size() && from.triangle.size() == from.size()) {
        to.bary[slot] = from.bary[k];
        to.triangle[slot] = from.triangle[k];
    }
}
}  // namespace

double FragmentSampler::uniform() {
    // In (0, 1): a logarithm's argument.
    return (double(rng_() >> 11) + 0.5) * (1.0 / 9007199254740992.0);
}

void FragmentSampler::skip() {
    // Li's Algorithm L (ACM TOMS 20(4), 1994): the gap to the next fragment that enters the
    // reservoir is geometric with the running weight w, so only O(count log(n / count))
    // fragments draw random numbers.
    w_ *= std::exp(std::log(uniform()) / double(count_));
    const double gap = std::floor(std::log(uniform()) / std::log1p(-w_));
    next_ = gap < 9e18 - double(next_) ? next_ + int64_t(gap) + 1 : INT64_MAX;
}

void FragmentSampler::add(const FragmentList& list) {
    for (size_t k = 0; k < list.size(); ++k, ++seen_) {
        if (count_ <= 0 || seen_ < count_) {
            append(kept_, list, k);
            order_.push_back(seen_);
            if (count_ > 0 && seen_ + 1 == count_) {
                next_ = seen_;
                skip();
            }
            continue;
        }
        if (seen_ < next_) {  // jump to the next fragment that enters
            const int64_t jump = std::min<int64_t>(next_ - seen_, int64_t(list.size() - k));
            k += size_t(jump) - 1;
            seen_ += jump - 1;
            continue;
        }
        const auto j = size_t(std::uniform_int_distribution<int64_t>(0, count_ - 1)(rng_));
        assign(kept_, j, list, k);
        order_[j] = seen_;
        skip();
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
