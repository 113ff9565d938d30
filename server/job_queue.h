#pragma once
// The bounded FIFO of queued job ids that the workers take from. In memory: the job store is
// the durable truth, and the queue is rebuilt from it at start-up.

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <mutex>
#include <optional>
#include <string>

namespace hexcover::server {

class JobQueue {
 public:
  /// `limit` is the most ids push() accepts (restore() may exceed it).
  explicit JobQueue(std::size_t limit) : limit_(limit) {}

  /// Appends `id`; false (nothing appended) when the queue is full or closed.
  bool push(const std::string& id);
  /// Appends `id` whatever the limit (jobs recovered at start-up were accepted already).
  void restore(const std::string& id);
  /// Waits for the oldest id and removes it; nullopt once the queue is closed.
  std::optional<std::string> pop();
  /// Removes `id`; false when it is not queued.
  bool remove(const std::string& id);
  /// 0-based position of `id` (0 = runs next), nullopt when not queued.
  std::optional<std::size_t> position(const std::string& id) const;
  std::size_t size() const;
  bool full() const;
  /// Wakes every pop() with nullopt and refuses further pushes; queued ids stay queued (durably
  /// in the store) for the next start.
  void close();

 private:
  const std::size_t limit_;
  mutable std::mutex mutex_;
  std::condition_variable available_;
  std::deque<std::string> ids_;
  bool closed_ = false;
};

}  // namespace hexcover::server
