// parallelFor and runBoth (core/common/concurrency.h): every index exactly once on any thread
// count and chunk size, uneven work included, and exceptions of the work reach the caller.

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/common/concurrency.h"

namespace hexcover {
namespace {

TEST(ParallelFor, VisitsEveryIndexOnceForAnyThreadCountAndChunk) {
  for (const std::size_t count : {0u, 1u, 5u, 1000u, 100003u})
    for (const int threads : {1, 2, 3})
      for (const std::size_t chunk : {std::size_t{1}, std::size_t{64}, std::size_t{2048}}) {
        const auto visits = std::make_unique<std::atomic<int>[]>(count);
        parallelFor(
            count, threads, [&](std::size_t i) { ++visits[i]; }, chunk);
        int wrong = 0;
        for (std::size_t i = 0; i < count; ++i) wrong += visits[i] != 1;
        EXPECT_EQ(wrong, 0) << count << " indices, " << threads << " threads, chunks of " << chunk;
      }
}

TEST(ParallelFor, GivesTheSameResultsWhenTheWorkPerIndexIsUneven) {
  // The costly indices are all in the first tenth, as where relaxation's moved vertices cluster.
  const std::size_t count = 4000;
  const auto work = [](std::size_t i) {
    double sum = 0.0;
    for (std::size_t k = 0; k < (i < 400 ? 20000u : 10u); ++k) sum += std::sqrt(double(i + k));
    return sum;
  };
  std::vector<double> one(count), two(count);
  parallelFor(
      count, 1, [&](std::size_t i) { one[i] = work(i); }, 16);
  parallelFor(
      count, 2, [&](std::size_t i) { two[i] = work(i); }, 16);
  EXPECT_EQ(one, two);
}

TEST(ParallelFor, RethrowsTheWorksExceptionAfterEveryThreadIsDone) {
  for (const int threads : {1, 2, 3}) {
    std::atomic<int> running{0};
    EXPECT_THROW(parallelFor(
                     10000, threads,
                     [&](std::size_t i) {
                       ++running;
                       if (i == 7777) throw std::runtime_error("index " + std::to_string(i));
                       --running;
                     },
                     16),
                 std::runtime_error);
    EXPECT_EQ(running.load(), 1) << threads << " threads";  // only the throwing body is unfinished
  }
}

TEST(RunBoth, RunsBothTasksAndPropagatesTheMainTasksException) {
  for (const int threads : {1, 2}) {
    bool mainRan = false, sideRan = false;
    runBoth(
        threads, [&] { mainRan = true; }, [&] { sideRan = true; });
    EXPECT_TRUE(mainRan && sideRan) << threads << " threads";
    sideRan = false;
    EXPECT_THROW(runBoth(
                     threads, [] { throw std::invalid_argument("main"); }, [&] { sideRan = true; }),
                 std::invalid_argument);
    EXPECT_TRUE(sideRan) << threads << " threads";
  }
}

}  // namespace
}  // namespace hexcover
