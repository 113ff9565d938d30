#pragma once
// The median of a sample, as the stages use it for a typical length or curvature.

#include <algorithm>
#include <vector>

namespace hexcover {

/// The upper median of `values` (the element at index size / 2 once sorted), 0 for none.
inline double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

}  // namespace hexcover
