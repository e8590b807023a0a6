// A plain 2D buffer with (x, y) access, row-major, y as the caller defines it.
#pragma once

#include <cstddef>
#include <vector>

namespace pgt {

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
