#include "background_job.h"

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

TEST(RunUninterruptible, ReturnsTheValueOrRethrows) {
  BackgroundJob job;
  std::atomic<int> value{0};
  std::atomic<bool> threw{false};
  job.start([&](const BackgroundJob::Ticket& t) {
    value = runUninterruptible<int>(t, [] { return 42; });
    try {
      runUninterruptible<int>(t, []() -> int { throw ParameterError("bad"); });
    } catch (const ParameterError&) {
      threw = true;
    }
  });
  job.finish();
  EXPECT_EQ(value.load(), 42);
  EXPECT_TRUE(threw.load());
}

TEST(RunUninterruptible, ACancelledJobStopsAtOnceAndLeavesTheWorkToFinish) {
  // The work cannot poll: it waits for a release the test gives only after the job has stopped.
  auto release = std::make_shared<std::atomic<bool>>(false);
  auto finished = std::make_shared<std::atomic<bool>>(false);
  std::atomic<bool> cancelled{false};
  BackgroundJob job;
  job.start([&, release, finished](const BackgroundJob::Ticket& t) {
    try {
      runUninterruptible<int>(t, [release, finished] {
        while (!*release) std::this_thread::sleep_for(std::chrono::milliseconds(1));
        *finished = true;
        return 1;
      });
    } catch (const Cancelled&) {
      cancelled = true;
    }
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  EXPECT_TRUE(job.stop());  // returns although the work is still blocked
  EXPECT_TRUE(cancelled.load());
  EXPECT_FALSE(finished->load());
  *release = true;  // the abandoned work ends by itself, on what it owns
  for (int i = 0; i < 5000 && !*finished; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  EXPECT_TRUE(finished->load());
}

}  // namespace
}  // namespace motionmap::studio
