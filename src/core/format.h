// Numbers as CSV text: `nan` for anything non-finite, printf precision otherwise.
#pragma once

#include <cmath>
#include <cstdio>
#include <string>

namespace pgt {

inline std::string formatNumber(double x, int significantDigits = 9) {
    if (!std::isfinite(x)) return "nan";
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.*g", significantDigits, x);
    return buf;
}

}  // namespace pgt
