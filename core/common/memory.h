#pragma once
// Process memory figures for reports and benchmarks (Linux /proc; 0 where unavailable).

#include <fstream>
#include <string>

namespace hexcover {

/// Peak resident set size of this process so far, in MiB (VmHWM).
inline double peakMemoryMiB() {
  std::ifstream status("/proc/self/status");
  std::string key;
  while (status >> key) {
    if (key == "VmHWM:") {
      double kib = 0.0;
      status >> kib;
      return kib / 1024.0;
    }
    status.ignore(1 << 12, '\n');
  }
  return 0.0;
}

}  // namespace hexcover
