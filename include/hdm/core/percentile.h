// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// The one quantile helper of hdm's statistics (latency figures, scenario scores, benchmarks).

#include <algorithm>
#include <cstddef>
#include <vector>

namespace hdm {

/// @brief The @p q-quantile of @p values by nearest rank: the element that would sit at index
/// min(n − 1, ⌊q·n⌋) if @p values were sorted (the median is index n/2).
/// @param values n numbers; reordered (std::nth_element), not otherwise changed.
/// @param q      quantile in [0, 1] (0.5 median, 0.95, 0.99).
/// @return that element, or T{} when @p values is empty.
/// @note O(n) expected; no allocation.
template <class T>
T percentile(std::vector<T>& values, double q) {
  if (values.empty()) return T{};
  const size_t k = std::min(values.size() - 1, static_cast<size_t>(q * static_cast<double>(values.size())));
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
  return values[k];
}

}  // namespace hdm
