#include "server/job_queue.h"

#include <algorithm>

namespace hexcover::server {

bool JobQueue::push(const std::string& id) {
  {
    const std::lock_guard lock(mutex_);
    if (closed_ || ids_.size() >= limit_) return false;
    ids_.push_back(id);
  }
  available_.notify_one();
  return true;
}

void JobQueue::restore(const std::string& id) {
  {
    const std::lock_guard lock(mutex_);
    ids_.push_back(id);
  }
  available_.notify_one();
}

std::optional<std::string> JobQueue::pop() {
  std::unique_lock lock(mutex_);
  available_.wait(lock, [&] { return closed_ || !ids_.empty(); });
  if (closed_) return std::nullopt;
  std::string id = std::move(ids_.front());
  ids_.pop_front();
  return id;
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

void JobQueue::close() {
  {
    const std::lock_guard lock(mutex_);
    closed_ = true;
  }
  available_.notify_all();
}

}  // namespace hexcover::server
