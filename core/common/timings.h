#pragma once
// Wall-clock timings of named steps, reported by every stage.

#include <chrono>
#include <string>
#include <utility>
#include <vector>

namespace hexcover {

struct StepTiming {
  std::string step;
  double seconds = 0.0;
};
using Timings = std::vector<StepTiming>;

/// Appends {step, elapsed seconds} to a Timings list when it goes out of scope.
class ScopedTimer {
 public:
  ScopedTimer(Timings& timings, std::string step)
      : timings_(timings), step_(std::move(step)), start_(std::chrono::steady_clock::now()) {}
  ~ScopedTimer() {
    const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start_;
    timings_.push_back({std::move(step_), elapsed.count()});
  }
  ScopedTimer(const ScopedTimer&) = delete;
  ScopedTimer& operator=(const ScopedTimer&) = delete;

 private:
  Timings& timings_;
  std::string step_;
  std::chrono::steady_clock::time_point start_;
};

/// Sum of all step times.
inline double totalSeconds(const Timings& timings) {
  double total = 0.0;
  for (const auto& t : timings) total += t.seconds;
  return total;
}

}  // namespace hexcover
