// The job queue's slots: a queued job starts only in a free slot; a job that suspends (waiting for
// memory) lets the next queued one start, and when it resumes it goes before the queued jobs.

#include "server/job_queue.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <optional>
#include <thread>

namespace hexcover::server {
namespace {

/// Pops on its own thread; taken() once it has an id and a slot.
class Popper {
 public:
  explicit Popper(JobQueue& queue)
      : thread_([this, &queue] {
          if (auto taken = queue.pop()) taken_.emplace(std::move(*taken));
          done_ = true;
        }) {}
  ~Popper() { thread_.join(); }
  bool doneSoon() const {
    for (int i = 0; i < 1000 && !done_; ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    return done_;
  }
  bool doneAfterAWhile() const {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    return done_;
  }
  /// Waits for the thread and returns what it took.
  std::optional<JobQueue::Taken> take() {
    thread_.join();
    thread_ = std::thread([] {});
    return std::move(taken_);
  }

 private:
  std::atomic<bool> done_{false};
  std::optional<JobQueue::Taken> taken_;
  std::thread thread_;
};

TEST(JobQueue, AJobStartsOnlyInAFreeSlot) {
  JobQueue queue(10, 1);
  ASSERT_TRUE(queue.push("a"));
  ASSERT_TRUE(queue.push("b"));
  std::optional<JobQueue::Taken> a = queue.pop();
  ASSERT_TRUE(a);
  EXPECT_EQ(a->id, "a");
  EXPECT_EQ(queue.busySlots(), 1);
  Popper b(queue);
  EXPECT_FALSE(b.doneAfterAWhile()) << "the only slot is a's";
  EXPECT_EQ(queue.position("b"), 0u);
  a.reset();  // a ends
  ASSERT_TRUE(b.doneSoon());
  EXPECT_EQ(b.take()->id, "b");
  EXPECT_EQ(queue.busySlots(), 0);
}

TEST(JobQueue, ASuspendedJobLetsTheNextOneStartAndResumesBeforeTheQueue) {
  JobQueue queue(10, 1);
  for (const char* id : {"a", "b", "c"}) ASSERT_TRUE(queue.push(id));
  std::optional<JobQueue::Taken> a = queue.pop();
  ASSERT_TRUE(a);
  a->slot.suspend();  // a waits for memory
  EXPECT_EQ(queue.busySlots(), 0);
  std::optional<JobQueue::Taken> b = queue.pop();
  ASSERT_TRUE(b);
  EXPECT_EQ(b->id, "b");

  std::atomic<bool> resumed{false};
  std::thread resume([&] {
    a->slot.resume();
    resumed = true;
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_FALSE(resumed) << "b holds the only slot";
  Popper c(queue);
  b.reset();  // b ends: its slot goes to the resuming a, not to the queued c
  resume.join();
  EXPECT_TRUE(resumed);
  EXPECT_FALSE(c.doneAfterAWhile());
  EXPECT_EQ(queue.busySlots(), 1);
  a.reset();
  ASSERT_TRUE(c.doneSoon());
  EXPECT_EQ(c.take()->id, "c");
}

TEST(JobQueue, CloseWakesWaitingPopsWithNothing) {
  JobQueue queue(10, 2);
  Popper waiting(queue);
  EXPECT_FALSE(waiting.doneAfterAWhile());
  queue.close();
  ASSERT_TRUE(waiting.doneSoon());
  EXPECT_FALSE(waiting.take());
  EXPECT_FALSE(queue.push("late"));
}

}  // namespace
}  // namespace hexcover::server
