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
        }
    return list;
}

FragmentList sampleFragments(const FragmentList& all, int count, uint32_t seed) {
    if (count <= 0 || size_t(count) >= all.size()) return all;
    std::vector<size_t> idx(all.size());
    for (size_t k = 0; k < idx.size(); ++k) idx[k] = k;
    std::mt19937 rng(seed);
    std::shuffle(idx.begin(), idx.end(), rng);
    idx.resize(size_t(count));
    std::sort(idx.begin(), idx.end());  // keep the scan order's memory locality
    FragmentList out;
    for (size_t k : idx) {
        out.pixel.push_back(all.pixel[k]);
        out.uv0.push_back(all.uv0[k]);
        out.view.push_back(all.view[k]);
        out.viewExact.push_back(all.viewExact[k]);
    }
    return out;
}

}  // namespace pgt
