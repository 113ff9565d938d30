#pragma once
// The memory that the running jobs share. A job announces its estimated peak before its heavy
// stages (RunContext::peakMemory); the first announcement waits until that much of the budget is
// free, so that jobs which would not fit side by side run one after the other instead of
// exhausting the machine (which would end the whole server). A job that would not fit even alone
// is refused. Later, larger announcements of a running job are granted without waiting (a job
// that holds memory never waits for another: no deadlock), as long as it fits the whole budget.
//
// Waiting jobs are served first come, first served without blocking smaller ones: memory that
// comes free while jobs wait is set aside for the longest-waiting one until it has its peak, and
// a job that fits in what is free and not set aside starts at once. So small jobs pass a large
// waiting one, and a stream of them cannot starve it.

#include <condition_variable>
#include <functional>
#include <list>
#include <mutex>

namespace hexcover::server {

class MemoryBudget {
 public:
  /// `totalMiB` > 0: what all running jobs may use together.
  explicit MemoryBudget(double totalMiB);
  MemoryBudget(const MemoryBudget&) = delete;
  MemoryBudget& operator=(const MemoryBudget&) = delete;

  double totalMiB() const { return total_; }
  double reservedMiB() const;

  /// One job's part of the budget, returned when the share is destroyed.
  class Share {
   public:
    explicit Share(MemoryBudget& budget) : budget_(budget) {}
    ~Share();
    Share(const Share&) = delete;
    Share& operator=(const Share&) = delete;

    /// Raises this job's part to `peakMiB` (a smaller value keeps it). The first raise waits
    /// while the other jobs' parts leave too little free, polling `stop` (which may throw, as
    /// RunContext::throwIfCanceled does) meanwhile. Throws Error(LimitExceeded) when `peakMiB`
    /// exceeds the whole budget.
    void raise(double peakMiB, const std::function<void()>& stop);
    double reservedMiB() const { return reserved_; }

   private:
    MemoryBudget& budget_;
    double reserved_ = 0.0;
  };

 private:
  /// A job waiting for its first part: `setAside` of its `need` is kept for it already.
  struct Waiter {
    double need;
    double setAside = 0.0;
    bool granted = false;
  };
  /// What is neither reserved nor set aside (negative while running jobs' raises overcommit).
  double unclaimedLocked() const { return total_ - reserved_ - setAside_; }
  /// `freedMiB` came free: sets it aside for the waiters in order, then grants whom it can.
  void distributeLocked(double freedMiB);
  /// Grants, in order, every waiter whose rest fits in the unclaimed memory.
  void grantLocked();

  const double total_;
  mutable std::mutex mutex_;
  std::condition_variable freed_;
  double reserved_ = 0.0;
  double setAside_ = 0.0;      ///< sum of the waiters' setAside
  std::list<Waiter> waiters_;  ///< first come first
};

/// The memory this process may use in MiB: the physical memory, capped by the cgroup's memory
/// limit (v2 memory.max, or v1 memory.limit_in_bytes) when there is one.
double usableMemoryMiB();

}  // namespace hexcover::server
