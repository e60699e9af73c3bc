// SPDX-License-Identifier: MIT
#pragma once
// Block-parallel loops for hdm::core on std::thread alone, so that a program that loads, queries,
// renders forces and edits a model links Eigen and nothing heavier. Used only off the
// servo thread (model loading and rebuilds); the bake's libraries keep TBB.

#include <algorithm>
#include <cstddef>
#include <exception>
#include <thread>
#include <vector>

namespace hdm::core::detail {

/// Number of `worker` values parallel_blocks() may pass for @p count elements in blocks of @p grain.
inline size_t parallel_workers(size_t count, size_t grain) {
  const size_t blocks = (count + grain - 1) / std::max<size_t>(grain, 1);
  return std::max<size_t>(1, std::min<size_t>(blocks, std::max(1u, std::thread::hardware_concurrency())));
}

/// Calls `body(begin, end, worker)` over disjoint blocks covering [0, count), each at least
/// `grain` long, on up to std::thread::hardware_concurrency() threads (the caller's among them);
/// `worker` in [0, workers) is the same for every block one thread runs, for per-thread scratch.
/// Returns when every block is done and rethrows the first exception a block threw.
/// Cost: one thread start per extra worker (tens of µs), so use it for loops of milliseconds.
template <class Body>
void parallel_blocks(size_t count, size_t grain, Body&& body) {
  const size_t workers = parallel_workers(count, grain);
  if (workers <= 1) {
    if (count > 0) body(size_t(0), count, size_t(0));
    return;
  }
  // Contiguous ranges, one per worker: the loops here cost the same per element.
  std::vector<std::exception_ptr> errors(workers);
  auto run = [&](size_t w) {
    const size_t begin = count * w / workers, end = count * (w + 1) / workers;
    try {
      body(begin, end, w);
    } catch (...) {
      errors[w] = std::current_exception();
    }
  };
  std::vector<std::thread> threads;
  threads.reserve(workers - 1);
  for (size_t w = 1; w < workers; ++w) threads.emplace_back(run, w);
  run(0);
  for (auto& t : threads) t.join();
  for (auto& e : errors)
    if (e) std::rethrow_exception(e);
}

}  // namespace hdm::core::detail
