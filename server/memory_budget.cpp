#include "server/memory_budget.h"

#include <unistd.h>

#include <algorithm>
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
    budget_.distributeLocked(reserved_);
  }
  budget_.freed_.notify_all();
}

void MemoryBudget::distributeLocked(double freedMiB) {
  // Only what is really free of it: running jobs may hold more than the budget for a while.
  double left = std::min(freedMiB, std::max(0.0, unclaimedLocked()));
  for (Waiter& waiter : waiters_) {
    if (left <= 0.0) break;
    if (waiter.granted) continue;
    const double part = std::min(left, waiter.need - waiter.setAside);
    waiter.setAside += part;
    setAside_ += part;
    left -= part;
  }
  grantLocked();
}

void MemoryBudget::grantLocked() {
  for (Waiter& waiter : waiters_)
    if (!waiter.granted && waiter.need - waiter.setAside <= unclaimedLocked()) {
      setAside_ -= waiter.setAside;
      reserved_ += waiter.need;
      waiter.setAside = 0.0;
      waiter.granted = true;
    }
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
  // A job that holds a part takes more at once; one that holds nothing starts at once only
  // when its peak fits in what the waiters have not claimed.
  if (reserved_ > 0.0 || peakMiB <= budget_.unclaimedLocked()) {
    budget_.reserved_ += peakMiB - reserved_;
    reserved_ = peakMiB;
    return;
  }
  const auto waiter = budget_.waiters_.insert(budget_.waiters_.end(), Waiter{peakMiB});
  while (!waiter->granted) {
    budget_.freed_.wait_for(lock, std::chrono::milliseconds(100));
    if (waiter->granted) break;
    lock.unlock();
    try {
      stop();
    } catch (...) {
      lock.lock();
      const double setAside = waiter->setAside;
      if (waiter->granted) reserved_ = peakMiB;  // the destructor returns it
      budget_.waiters_.erase(waiter);
      if (setAside > 0.0) {  // passed on to the next waiters
        budget_.setAside_ -= setAside;
        budget_.distributeLocked(setAside);
      }
      lock.unlock();
      budget_.freed_.notify_all();
      throw;
    }
    lock.lock();
  }
  budget_.waiters_.erase(waiter);
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
