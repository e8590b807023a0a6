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
            list.uv0.push_back(Vec2f(f.uv0));
            list.view.push_back(Vec3f(f.viewTangent));
            list.uv0d.push_back(f.uv0);
            list.viewd.push_back(f.viewTangent);
            list.viewExact.push_back(Vec3f(f.viewTangentExact));
            list.viewExactd.push_back(f.viewTangentExact);
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
        out.uv0d.push_back(all.uv0d[k]);
        out.viewd.push_back(all.viewd[k]);
        out.viewExact.push_back(all.viewExact[k]);
        out.viewExactd.push_back(all.viewExactd[k]);
    }
    return out;
}

}  // namespace pgt
