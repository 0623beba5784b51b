#include "motionmap/core/parallel.h"

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "motionmap/core/error.h"

namespace motionmap {
namespace {

TEST(ParallelFor, RunsEveryItemOnceAndReportsProgressUpToOne) {
  const int n = 1000;
  std::vector<std::atomic<int>> hits(n);
  std::vector<double> reports;
  const std::thread::id caller = std::this_thread::get_id();
  bool progress_off_caller = false;
  const Control control([&](double f, std::string_view) {
    progress_off_caller |= std::this_thread::get_id() != caller;
    reports.push_back(f);
  });
  parallel_for(
      n, [&](int i) { hits[i].fetch_add(1); }, control);
  for (int i = 0; i < n; ++i) ASSERT_EQ(hits[i].load(), 1) << i;
  EXPECT_FALSE(progress_off_caller);
  ASSERT_FALSE(reports.empty());
  EXPECT_LE(reports.size(), 102u);  // about a hundred, not one per item
  EXPECT_EQ(reports.back(), 1.0);
  for (std::size_t k = 1; k < reports.size(); ++k) EXPECT_LE(reports[k - 1], reports[k]);
}

TEST(ParallelFor, CancelStopsTheLoopWithCancelled) {
  // Only the calling thread polls, between its own items. Helpers wait in their first item until
  // cancel has said yes and then take a millisecond per item, so that on a machine with many
  // cores they can neither finish the loop before the caller has polled three times nor in the
  // moment between that answer and the loop's stop.
  std::atomic<int> ran{0};
  std::atomic<bool> cancelled{false};
  const std::thread::id caller = std::this_thread::get_id();
  int polls = 0;
  const Control control({}, [&] {
    cancelled = ++polls > 3;
    return cancelled.load();
  });
  auto body = [&](int) {
    if (std::this_thread::get_id() != caller) {
      while (!cancelled) std::this_thread::yield();
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    ran.fetch_add(1);
  };
  EXPECT_THROW(parallel_for(100000, body, control), Cancelled);
  EXPECT_EQ(polls, 4);  // before the loop, then after each of the caller's first three items
  EXPECT_LT(ran.load(), 100000);
  ran = 0;  // cancelled before it starts: nothing runs
  EXPECT_THROW(parallel_for(
                   10, [&](int) { ran.fetch_add(1); }, Control({}, [] { return true; })),
               Cancelled);
  EXPECT_EQ(ran.load(), 0);
}

TEST(ParallelFor, RethrowsTheBodysException) {
  EXPECT_THROW(parallel_for(1000,
                            [](int i) {
                              if (i == 500) throw std::runtime_error("item 500");
                            }),
               std::runtime_error);
  EXPECT_NO_THROW(parallel_for(0, [](int) { throw std::runtime_error("never"); }));
}

// Item 3 fails slowly while the other threads reach later failures first: the error is still
// item 3's, as a serial loop's would be.
TEST(ParallelFor, RethrowsTheLowestFailingItemsException) {
  for (int round = 0; round < 5; ++round) {
    try {
      parallel_for(200, [](int i) {
        if (i == 3) {
          std::this_thread::sleep_for(std::chrono::milliseconds(30));
          throw std::runtime_error("item 3");
        }
        if (i % 10 == 7) throw std::runtime_error("item " + std::to_string(i));
      });
      FAIL() << "no exception";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "item 3") << "round " << round;
    }
  }
}

TEST(ParallelChunks, WorkerIndicesIndexPerThreadScratch) {
  const int chunks = 64;
  const int workers = worker_count(chunks);
  EXPECT_GE(workers, 1);
  EXPECT_LE(workers, worker_count());
  std::vector<std::atomic<int>> per_worker(workers);
  std::atomic<int> bad{0};
  parallel_chunks(chunks, [&](int, int w) {
    if (w < 0 || w >= workers) {
      bad.fetch_add(1);
    } else {
      per_worker[w].fetch_add(1);
    }
  });
  EXPECT_EQ(bad.load(), 0);
  int total = 0;
  for (auto& c : per_worker) total += c.load();
  EXPECT_EQ(total, chunks);

  // serial: everything on the caller, as worker 0, ticking after every chunk
  std::vector<int> ticks;
  const std::thread::id caller = std::this_thread::get_id();
  bool elsewhere = false;
  parallel_chunks(
      5, [&](int, int w) { elsewhere |= w != 0 || std::this_thread::get_id() != caller; },
      [&](int done) { ticks.push_back(done); }, /*serial=*/true);
  EXPECT_FALSE(elsewhere);
  EXPECT_EQ(ticks, (std::vector<int>{1, 2, 3, 4, 5, 5}));  // and once more at the end
  EXPECT_EQ(worker_count(5, /*serial=*/true), 1);
}

TEST(ParallelChunks, AThrowingTickStopsTheOtherThreads) {
  // Helpers (worker ≥ 1) wait in their first chunk until the tick throws and then take a
  // millisecond per chunk, so that on a machine with many cores they cannot run every chunk
  // before the caller's tenth tick, nor in the moment between the throw and the stop.
  std::atomic<int> ran{0};
  std::atomic<bool> thrown{false};
  EXPECT_THROW(parallel_chunks(
                   100000,
                   [&](int, int worker) {
                     if (worker != 0) {
                       while (!thrown) std::this_thread::yield();
                       std::this_thread::sleep_for(std::chrono::milliseconds(1));
                     }
                     ran.fetch_add(1);
                   },
                   [&](int done) {
                     if (done >= 10) {
                       thrown = true;
                       throw Cancelled();
                     }
                   }),
               Cancelled);
  EXPECT_LT(ran.load(), 100000);
}

}  // namespace
}  // namespace motionmap
