#include "server/memory_budget.h"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>

#include "core/common/error.h"

namespace hexcover::server {

MemoryBudget::MemoryBudget(double totalMiB) : total_(totalMiB) {}

double MemoryBudget::reservedMiB() const {
  const std::lock_guard lock(mutex_);
  return reserved_;
}

MemoryBudget::Share::~Share() {
  if (reserved_ <= 0.0) return;
  {
    const std::lock_guard lock(budget_.mutex_);
    budget_.reserved_ -= reserved_;
  }
  budget_.freed_.notify_all();
}

void MemoryBudget::Share::raise(double peakMiB, const std::function<void()>& stop) {
  if (!(peakMiB > reserved_)) return;
  if (peakMiB > budget_.total_) {
    std::ostringstream message;
    message << "this job needs about " << std::lround(peakMiB)
            << " MiB of memory (estimated from its faces and vertex count), more than the "
            << std::lround(budget_.total_)
            << " MiB this server gives its jobs: give fewer vertices (a larger edge length) or a "
               "smaller mesh, or start the server with a larger --memory-budget";
    throw Error(ErrorCode::LimitExceeded, message.str());
  }
  std::unique_lock lock(budget_.mutex_);
  // Only a job that holds nothing waits; one that holds a part takes more at once.
  if (reserved_ <= 0.0)
    while (budget_.reserved_ + peakMiB > budget_.total_) {
      budget_.freed_.wait_for(lock, std::chrono::milliseconds(100));
      lock.unlock();
      stop();
      lock.lock();
    }
  budget_.reserved_ += peakMiB - reserved_;
  reserved_ = peakMiB;
}

namespace {

/// The first number in `path`, or nothing (missing file, or "max": no limit).
std::optional<double> numberIn(const char* path) {
  std::ifstream in(path);
  double value = 0.0;
  if (in >> value && value > 0.0) return value;
  return std::nullopt;
}

}  // namespace

double usableMemoryMiB() {
  constexpr double kMiB = 1024.0 * 1024.0;
  const double pages = static_cast<double>(sysconf(_SC_PHYS_PAGES));
  const double pageBytes = static_cast<double>(sysconf(_SC_PAGESIZE));
  double bytes = pages > 0 && pageBytes > 0 ? pages * pageBytes : 4096.0 * kMiB;
  // cgroup v1 reports "no limit" as a huge number, which the minimum leaves out.
  for (const char* limit :
       {"/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"})
    if (const auto value = numberIn(limit)) bytes = std::min(bytes, *value);
  return bytes / kMiB;
}

}  // namespace hexcover::server
