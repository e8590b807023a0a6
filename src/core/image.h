// A plain 2D buffer with (x, y) access, row-major, y as the caller defines it.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace pgt {

// Pixels [x0, x1) x [y0, y1).
struct PixelRect {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    bool empty() const { return x1 <= x0 || y1 <= y0; }
    int width() const { return x1 - x0; }
    int height() const { return y1 - y0; }
};

template <class T>
struct Image2D {
    int width = 0;
    int height = 0;
    std::vector<T> data;

    Image2D() = default;
    Image2D(int w, int h, const T& fill = T()) : width(w), height(h), data(size_t(w) * h, fill) {}

    T& at(int x, int y) { return data[size_t(y) * width + x]; }
    const T& at(int x, int y) const { return data[size_t(y) * width + x]; }
    size_t size() const { return data.size(); }
};

// `image` as w x h pixels of T{}: made anew when its size differs, else cleared over all cores
// (a buffer kept from band to band).
template <class T>
void resetImage(Image2D<T>& image, int w, int h) {
    if (image.width != w || image.height != h) {
        image = Image2D<T>(w, h);
        return;
    }
    tbb::parallel_for(tbb::blocked_range<size_t>(0, image.data.size(), size_t(1) << 14),
                      [&](const tbb::blocked_range<size_t>& r) {
                          std::fill(image.data.begin() + int64_t(r.begin()),
                                    image.data.begin() + int64_t(r.end()), T{});
                      });
}

// `image` as w x h pixels: made anew (T{}) when its size differs, else kept as it is, for a
// caller that writes every pixel (a buffer kept from band to band, not cleared twice).
template <class T>
void sizeImage(Image2D<T>& image, int w, int h) {
    if (image.width != w || image.height != h) image = Image2D<T>(w, h);
}

// Rows [band.y0, band.y1) of a whole-frame image.
template <class T>
Image2D<T> rowsOf(const Image2D<T>& full, PixelRect band) {
    Image2D<T> out(band.width(), band.height());
    std::copy_n(full.data.begin() + int64_t(band.y0) * full.width, out.size(), out.data.begin());
    return out;
}

}  // namespace pgt
