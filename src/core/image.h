// A plain 2D buffer with (x, y) access, row-major, y as the caller defines it.
#pragma once

#include <cstddef>
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

}  // namespace pgt
