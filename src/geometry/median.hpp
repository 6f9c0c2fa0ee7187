#pragma once
// The median of a sample (internal to the geometry library).
#include <algorithm>
#include <cstddef>
#include <vector>

namespace decalcomp::geometry {

// The upper median (element size/2 in sorted order); 0 for an empty sample.
inline double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
    return v[v.size() / 2];
}

}  // namespace decalcomp::geometry
