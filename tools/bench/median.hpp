#pragma once
// The bench's summary statistic: the median of repeated timings (0 for none).
#include <algorithm>
#include <vector>

namespace decalcomp::bench {

inline double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace decalcomp::bench
