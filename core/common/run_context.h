#pragma once
// Progress reporting and cooperative cancellation for long-running stages.
// Knows nothing about jobs or HTTP: the server, the CLI and tests all fill it in their own way.

#include <functional>
#include <string_view>

#include "core/common/error.h"

namespace hexcover {

/// The pipeline's stages, as its progress reports and its timings name them (the server places a
/// job's progress by these names).
namespace stage {
inline constexpr char kRepair[] = "repair";
inline constexpr char kField[] = "field";
inline constexpr char kParameterization[] = "parameterization";
inline constexpr char kExtraction[] = "extraction";
/// A parameterization and extraction after the first (the vertex count or the input's topology
/// was missed, or along a second field): one stage whose fraction only rises.
inline constexpr char kRerun[] = "rerun";
inline constexpr char kMetrics[] = "metrics";
}  // namespace stage

struct RunContext {
  /// Called with the stage name and the fraction of that stage done, in [0, 1]. May be empty.
  std::function<void(std::string_view stage, double fraction)> progress;
  /// Returns true when the caller wants the run to stop. May be empty.
  std::function<bool()> cancelRequested;
  /// Called with the run's estimated peak memory in MiB once it is known (the remesh pipeline:
  /// before the repair, for the input's faces, and after it, with the remesh's size, before the
  /// field), and again with a larger estimate when the run grows.
  /// A caller that runs several jobs side by side may wait there until the memory is free, or
  /// throw Error(LimitExceeded) to refuse a run too large for it. May be empty.
  std::function<void(double peakMiB)> peakMemory;

  void report(std::string_view stage, double fraction) const {
    if (progress) progress(stage, fraction);
  }
  void reservePeakMemory(double peakMiB) const {
    if (peakMemory) peakMemory(peakMiB);
  }
  /// Throws Error(Canceled) when cancellation was requested; call between and inside long steps.
  void throwIfCanceled() const {
    if (cancelRequested && cancelRequested()) throw Error(ErrorCode::Canceled, "the run was canceled");
  }
};

}  // namespace hexcover
