#pragma once
// The two ways core stages use more than one thread. Both give the same results for any thread
// count: the work is split so that no result depends on which thread computed it.

#include <algorithm>
#include <cstddef>
#include <future>
#include <thread>
#include <utility>
#include <vector>

namespace hexcover {

/// Runs body(i) for i in [0, count) on up to `threads` threads, in contiguous chunks of at least
/// `minChunk` indices.
template <typename Body>
void parallelFor(std::size_t count, int threads, const Body& body, std::size_t minChunk = 2048) {
  const std::size_t workers = std::min<std::size_t>(
      std::max(1, threads), std::max<std::size_t>(1, count / std::max<std::size_t>(1, minChunk)));
  if (workers <= 1) {
    for (std::size_t i = 0; i < count; ++i) body(i);
    return;
  }
  std::vector<std::thread> pool;
  pool.reserve(workers);
  for (std::size_t w = 0; w < workers; ++w) {
    pool.emplace_back([&, w] {
      const std::size_t begin = count * w / workers, end = count * (w + 1) / workers;
      for (std::size_t i = begin; i < end; ++i) body(i);
    });
  }
  for (auto& t : pool) t.join();
}

/// Runs two independent tasks: `side` on a second thread while `main` runs on this one when
/// threads ≥ 2, else `side` and then `main` on this thread. Returns when both are done; an
/// exception of `main`, else of `side`, propagates.
template <typename Main, typename Side>
void runBoth(int threads, Main&& main, Side&& side) {
  if (threads < 2) {
    side();
    main();
    return;
  }
  std::future<void> sideDone = std::async(std::launch::async, std::forward<Side>(side));
  try {
    main();
  } catch (...) {
    sideDone.wait();
    throw;
  }
  sideDone.get();
}

}  // namespace hexcover
