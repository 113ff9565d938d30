#pragma once
// The two ways core stages use more than one thread. Both give the same results for any thread
// count: the work is split so that no result depends on which thread computed it.

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <future>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

namespace hexcover {

/// Runs body(i) for i in [0, count) on up to `threads` threads (this one included): chunks of
/// `minChunk` consecutive indices, handed out in order to whichever thread is free, so that
/// uneven work per index still keeps every thread busy. An exception of body stops the handing
/// out; the first one is rethrown here once every thread is done.
template <typename Body>
void parallelFor(std::size_t count, int threads, const Body& body, std::size_t minChunk = 2048) {
  const std::size_t chunk = std::max<std::size_t>(1, minChunk);
  const std::size_t workers =
      std::min<std::size_t>(std::max(1, threads), std::max<std::size_t>(1, count / chunk));
  if (workers <= 1) {
    for (std::size_t i = 0; i < count; ++i) body(i);
    return;
  }
  std::atomic<std::size_t> next{0};
  std::mutex failure;
  std::exception_ptr first;
  const auto work = [&] {
    try {
      for (std::size_t begin; (begin = next.fetch_add(chunk)) < count;)
        for (std::size_t i = begin, end = std::min(count, begin + chunk); i < end; ++i) body(i);
    } catch (...) {
      next = count;
      const std::lock_guard<std::mutex> lock(failure);
      if (!first) first = std::current_exception();
    }
  };
  std::vector<std::thread> pool;
  pool.reserve(workers - 1);
  for (std::size_t w = 1; w < workers; ++w) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
  if (first) std::rethrow_exception(first);
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
