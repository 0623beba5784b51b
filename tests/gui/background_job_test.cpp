#include "common/background_job.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

namespace motionmap::studio {
namespace {

TEST(BackgroundJob, StopCancelsWaitsAndMakesTheJobStale) {
  BackgroundJob job;
  EXPECT_FALSE(job.running());
  EXPECT_FALSE(job.stop());
  std::atomic<int> seen_generation{-1};
  std::atomic<bool> saw_cancel{false};
  job.start([&](const BackgroundJob::Ticket& t) {
    seen_generation = t.generation;
    while (!t.cancelled()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    saw_cancel = true;
  });
  EXPECT_TRUE(job.running());
  EXPECT_TRUE(job.stop());  // returns once the thread has seen the flag and ended
  EXPECT_TRUE(saw_cancel.load());
  EXPECT_FALSE(job.running());
  EXPECT_FALSE(job.current(seen_generation.load()));
}

TEST(BackgroundJob, ANewJobMakesTheOldOnesResultsStale) {
  BackgroundJob job;
  std::atomic<int> first{-1}, second{-1};
  job.start([&](const BackgroundJob::Ticket& t) { first = t.generation; });
  job.start([&](const BackgroundJob::Ticket& t) { second = t.generation; });  // stops the first
  job.finish();
  EXPECT_FALSE(job.running());
  EXPECT_FALSE(job.current(first.load()));
  EXPECT_TRUE(job.current(second.load()));  // finished, not stopped: its result is wanted
}

}  // namespace
}  // namespace motionmap::studio
