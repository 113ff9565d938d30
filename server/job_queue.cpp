#include "server/job_queue.h"

#include <algorithm>

namespace hexcover::server {

JobQueue::JobQueue(std::size_t limit, int slots)
    : limit_(limit), slots_(std::max(1, slots)), freeSlots_(slots_) {}

JobQueue::Slot::~Slot() {
  if (held_) queue_->releaseSlot();
}

JobQueue::Slot::Slot(Slot&& other) noexcept : queue_(other.queue_), held_(other.held_) {
  other.held_ = false;
}

void JobQueue::Slot::suspend() {
  if (!held_) return;
  held_ = false;
  queue_->releaseSlot();
}

void JobQueue::Slot::resume() {
  if (held_) return;
  queue_->takeSlot();
  held_ = true;
}

void JobQueue::releaseSlot() {
  {
    const std::lock_guard lock(mutex_);
    ++freeSlots_;
  }
  changed_.notify_all();
}

void JobQueue::takeSlot() {
  std::unique_lock lock(mutex_);
  ++resuming_;
  changed_.wait(lock, [&] { return freeSlots_ > 0; });
  --resuming_;
  --freeSlots_;
}

bool JobQueue::push(const std::string& id) {
  {
    const std::lock_guard lock(mutex_);
    if (closed_ || ids_.size() >= limit_) return false;
    ids_.push_back(id);
  }
  changed_.notify_all();
  return true;
}

void JobQueue::restore(const std::string& id) {
  {
    const std::lock_guard lock(mutex_);
    ids_.push_back(id);
  }
  changed_.notify_all();
}

std::optional<JobQueue::Taken> JobQueue::pop() {
  std::unique_lock lock(mutex_);
  changed_.wait(lock, [&] { return closed_ || (!ids_.empty() && freeSlots_ > resuming_); });
  if (closed_) return std::nullopt;
  --freeSlots_;
  Taken taken{std::move(ids_.front()), Slot(*this)};
  ids_.pop_front();
  return taken;
}

bool JobQueue::remove(const std::string& id) {
  const std::lock_guard lock(mutex_);
  const auto it = std::find(ids_.begin(), ids_.end(), id);
  if (it == ids_.end()) return false;
  ids_.erase(it);
  return true;
}

std::optional<std::size_t> JobQueue::position(const std::string& id) const {
  const std::lock_guard lock(mutex_);
  const auto it = std::find(ids_.begin(), ids_.end(), id);
  if (it == ids_.end()) return std::nullopt;
  return std::size_t(it - ids_.begin());
}

std::size_t JobQueue::size() const {
  const std::lock_guard lock(mutex_);
  return ids_.size();
}

bool JobQueue::full() const {
  const std::lock_guard lock(mutex_);
  return ids_.size() >= limit_;
}

int JobQueue::busySlots() const {
  const std::lock_guard lock(mutex_);
  return slots_ - freeSlots_;
}

void JobQueue::close() {
  {
    const std::lock_guard lock(mutex_);
    closed_ = true;
  }
  changed_.notify_all();
}

}  // namespace hexcover::server
