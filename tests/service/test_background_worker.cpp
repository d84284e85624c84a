// BackgroundWorker: the LOCALIZE search thread of the router (docs/relocalization.md,
// "Threading"): jobs in order, continuations on the owner's thread, the bound, a clean stop.
#include <gtest/gtest.h>

#include <chrono>
#include <future>
#include <optional>
#include <thread>
#include <vector>

#include "service/background_worker.hpp"

namespace socc::service {
namespace {

using namespace std::chrono_literals;

// Runs the finished continuations until n have run (at most 10 s).
std::size_t collect(BackgroundWorker& worker, std::size_t n) {
  std::size_t ran = 0;
  const auto until = std::chrono::steady_clock::now() + 10s;
  while (ran < n && std::chrono::steady_clock::now() < until) {
    ran += worker.runFinished();
    std::this_thread::sleep_for(1ms);
  }
  return ran;
}

TEST(BackgroundWorker, RunsJobsInOrderAndContinuationsOnTheOwnersThread) {
  BackgroundWorker worker(4);
  std::vector<int> order;
  std::vector<std::thread::id> job_threads(3), continuation_threads(3);
  for (int i = 0; i < 3; ++i)
    ASSERT_TRUE(worker.submit([&, i](const std::atomic<bool>&) {
      job_threads[i] = std::this_thread::get_id();
      return BackgroundWorker::Continuation([&, i] {
        order.push_back(i);
        continuation_threads[i] = std::this_thread::get_id();
      });
    }));
  EXPECT_EQ(collect(worker, 3), 3u);
  EXPECT_EQ(order, (std::vector<int>{0, 1, 2}));
  for (int i = 0; i < 3; ++i) {
    EXPECT_NE(job_threads[i], std::this_thread::get_id());
    EXPECT_EQ(continuation_threads[i], std::this_thread::get_id());
  }
  EXPECT_EQ(worker.outstanding(), 0u);
}

// One job under way (running or finished, its continuation not run yet) plus max_waiting.
TEST(BackgroundWorker, RefusesJobsBeyondTheOneRunningAndMaxWaiting) {
  BackgroundWorker worker(1);
  std::promise<void> release;
  std::shared_future<void> released = release.get_future().share();
  const auto blocked = [released](const std::atomic<bool>&) {
    released.wait();
    return BackgroundWorker::Continuation([] {});
  };
  EXPECT_TRUE(worker.hasRoom());
  ASSERT_TRUE(worker.submit(blocked));
  ASSERT_TRUE(worker.submit(blocked));
  EXPECT_FALSE(worker.hasRoom());
  EXPECT_FALSE(worker.submit(blocked));
  EXPECT_EQ(worker.outstanding(), 2u);
  release.set_value();
  EXPECT_EQ(collect(worker, 2), 2u);
  EXPECT_TRUE(worker.hasRoom());
}

// A running job that only ends when cancelled: the destructor cancels it, drops the waiting
// one and joins; no continuation runs.
TEST(BackgroundWorker, StopsWithARunningJobWithoutRunningContinuations) {
  bool continued = false;
  std::promise<void> started;
  const auto start = std::chrono::steady_clock::now();
  {
    BackgroundWorker worker(2);
    ASSERT_TRUE(worker.submit([&](const std::atomic<bool>& cancelled) {
      started.set_value();
      while (!cancelled.load()) std::this_thread::sleep_for(1ms);
      return BackgroundWorker::Continuation([&] { continued = true; });
    }));
    ASSERT_TRUE(worker.submit([&](const std::atomic<bool>&) {
      return BackgroundWorker::Continuation([&] { continued = true; });
    }));
    started.get_future().wait();
  }
  EXPECT_FALSE(continued);
  EXPECT_LT(std::chrono::steady_clock::now() - start, 5s);
}

TEST(BackgroundWorker, AThrowingJobIsDroppedAndTheWorkerGoesOn) {
  BackgroundWorker worker(2);
  bool continued = false;
  ASSERT_TRUE(
      worker.submit([](const std::atomic<bool>&) -> BackgroundWorker::Continuation { throw 1; }));
  ASSERT_TRUE(worker.submit([&](const std::atomic<bool>&) {
    return BackgroundWorker::Continuation([&] { continued = true; });
  }));
  EXPECT_EQ(collect(worker, 2), 2u);  // the dropped job's empty continuation counts
  EXPECT_TRUE(continued);
}

}  // namespace
}  // namespace socc::service
