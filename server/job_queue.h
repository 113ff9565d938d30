#pragma once
// The bounded FIFO of queued job ids that the workers take from, and the slots in which taken
// jobs compute (one per worker). In memory: the job store is the durable truth, and the queue is
// rebuilt from it at start-up.
//
// A job that has to wait for something other than the CPU (its memory, memory_budget.h) gives
// its slot back meanwhile, so that the next queued job can run on it instead of queueing behind
// the waiting one; when its wait ends it takes a slot again, ahead of the queued jobs.

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <mutex>
#include <optional>
#include <string>

namespace hexcover::server {

class JobQueue {
 public:
  /// `limit` is the most ids push() accepts (restore() may exceed it); `slots` (>= 1) is how
  /// many taken jobs compute at once.
  JobQueue(std::size_t limit, int slots);

  /// A taken job's right to compute: one of the queue's slots, given back when destroyed.
  class Slot {
   public:
    explicit Slot(JobQueue& queue) : queue_(&queue) {}
    ~Slot();
    Slot(Slot&& other) noexcept;
    Slot& operator=(Slot&&) = delete;
    Slot(const Slot&) = delete;
    Slot& operator=(const Slot&) = delete;

    /// Gives the slot back while the job waits for something else.
    void suspend();
    /// Waits for a free slot and takes it; resuming jobs go before queued ones.
    void resume();

   private:
    JobQueue* queue_;
    bool held_ = true;
  };

  struct Taken {
    std::string id;
    Slot slot;
  };

  /// Appends `id`; false (nothing appended) when the queue is full or closed.
  bool push(const std::string& id);
  /// Appends `id` whatever the limit (jobs recovered at start-up were accepted already).
  void restore(const std::string& id);
  /// Waits until an id is queued and a slot is free, and takes both (the oldest id); nullopt
  /// once the queue is closed.
  std::optional<Taken> pop();
  /// Removes `id`; false when it is not queued.
  bool remove(const std::string& id);
  /// 0-based position of `id` (0 = runs next), nullopt when not queued.
  std::optional<std::size_t> position(const std::string& id) const;
  std::size_t size() const;
  bool full() const;
  int slots() const { return slots_; }
  /// Slots that taken jobs hold now.
  int busySlots() const;
  /// Wakes every pop() with nullopt and refuses further pushes; queued ids stay queued (durably
  /// in the store) for the next start. Taken jobs keep their slots and can still resume.
  void close();

 private:
  void releaseSlot();
  void takeSlot();

  const std::size_t limit_;
  const int slots_;
  mutable std::mutex mutex_;
  std::condition_variable changed_;  ///< an id was queued, a slot came free, or closed
  std::deque<std::string> ids_;
  int freeSlots_;
  int resuming_ = 0;  ///< jobs waiting in Slot::resume(), served before pop()
  bool closed_ = false;
};

}  // namespace hexcover::server
