// The ROS 1 bag reader starts its child process from a program that already runs threads:
// odom_client has LCM threads and TBB workers. A child forked without exec keeps every lock
// another thread held at the fork held for good; under ASan (GCC 12) this test deadlocked the
// forked child in ASan's allocator, hence the helper program started by posix_spawn
// (docs/sensors_bags.md). Here other threads allocate and free (small and mmap-sized blocks),
// hold a mutex, throw and catch exceptions, format through iostreams and run a TBB
// parallel_for, all in a loop, while the bag is read through the child many times and a
// damaged bag makes the child throw. Every read must come back complete and identical; a
// watchdog ends the process (and its children) if a child deadlocks.
#include <gtest/gtest.h>
#include <tbb/parallel_for.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <vector>

#include "bag_test_data.hpp"
#include "bags/bag_reader.hpp"

namespace socc::sensors::bags {
namespace {

namespace fs = std::filesystem;

constexpr int kReads = 30;
constexpr auto kDeadline = std::chrono::seconds(300);  // a read takes < 1 s, ASan included

/// Threads that keep the allocator, a mutex, the unwinder, iostreams and TBB busy until
/// destroyed.
class BusyThreads {
 public:
  BusyThreads() {
    for (int t = 0; t < 3; ++t) threads_.emplace_back([this, t] { churn(t); });
    threads_.emplace_back([this] { parallelFor(); });
  }
  ~BusyThreads() {
    stop_ = true;
    for (std::thread& t : threads_) t.join();
  }
  BusyThreads(const BusyThreads&) = delete;
  BusyThreads& operator=(const BusyThreads&) = delete;
  std::uint64_t rounds() const { return rounds_; }

 private:
  void churn(int seed) {
    std::uint64_t x = 0x9E3779B97F4A7C15ull * static_cast<std::uint64_t>(seed + 1);
    while (!stop_) {
      x ^= x << 13, x ^= x >> 7, x ^= x << 17;
      const std::size_t bytes = x % 4 == 0 ? (1u << 20) + x % 4096 : 16 + x % 2048;
      {
        const std::lock_guard<std::mutex> lock(mutex_);
        void* p = std::malloc(bytes);
        if (p != nullptr) static_cast<volatile char*>(p)[0] = 1;
        std::free(p);
      }
      try {
        throw std::runtime_error("unwind " + std::to_string(x));
      } catch (const std::runtime_error& e) {
        std::ostringstream text;
        text << e.what() << ' ' << static_cast<double>(x % 1000) / 7.0;
        if (text.str().empty()) std::abort();
      }
      ++rounds_;
    }
  }

  void parallelFor() {
    while (!stop_) {
      tbb::parallel_for(0, 256, [](int i) {
        std::vector<double> v(static_cast<std::size_t>(64 + i));
        v.back() = i;
      });
      ++rounds_;
    }
  }

  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> rounds_{0};
  std::mutex mutex_;
  std::vector<std::thread> threads_;
};

/// SIGKILLs this process's children (a deadlocked reader child would outlive the test).
void killChildren() {
  const std::string self = std::to_string(::getpid());
  for (const fs::directory_entry& e : fs::directory_iterator("/proc")) {
    std::ifstream stat(e.path() / "stat");
    std::string pid, comm, state, ppid;
    if (!(stat >> pid >> comm >> state >> ppid) || ppid != self) continue;
    ::kill(static_cast<pid_t>(std::stol(pid)), SIGKILL);
  }
}

/// Ends the process (and its children) when not disarmed before the deadline: a deadlocked
/// child blocks the parent in read() for good, and the test must fail, not hang.
class Watchdog {
 public:
  explicit Watchdog(std::chrono::seconds deadline)
      : thread_([this, deadline] {
          std::unique_lock<std::mutex> lock(mutex_);
          if (!done_cv_.wait_for(lock, deadline, [this] { return done_; })) {
            std::fprintf(stderr, "a forked bag reader did not finish within %lld s: deadlock\n",
                         static_cast<long long>(deadline.count()));
            killChildren();
            std::_Exit(1);
          }
        }) {}
  ~Watchdog() {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      done_ = true;
    }
    done_cv_.notify_one();
    thread_.join();
  }
  Watchdog(const Watchdog&) = delete;
  Watchdog& operator=(const Watchdog&) = delete;

 private:
  std::mutex mutex_;
  std::condition_variable done_cv_;
  bool done_ = false;
  std::thread thread_;
};

std::vector<BagMessage> readBagMessages(const fs::path& file) {
  std::unique_ptr<BagReader> reader = openBagReader(file);
  std::vector<BagMessage> messages;
  while (std::optional<BagMessage> m = reader->next()) messages.push_back(std::move(*m));
  EXPECT_EQ(reader->problems(), "");
  return messages;
}

TEST(ForkedReaderUnderThreads, ReadsTheBagWhileOtherThreadsAllocateAndLock) {
  SOCC_REQUIRE_DATA(test::sharedData() / "kitti_00_first16");
  const fs::path file = fs::path(SOCC_BAG_FIXTURES_DIR) / "clouds_lz4.bag";
  ASSERT_TRUE(fs::exists(file)) << file << " missing: run the fixture sensors.bag_writers";
  const std::vector<BagMessage> expected = readBagMessages(file);  // before any other thread runs
  ASSERT_FALSE(expected.empty());
  // Half the bag: the child's open throws (an exception thrown in the child).
  const fs::path cut =
      fs::temp_directory_path() / ("socc_test_fork_threads_" + std::to_string(::getpid()) + ".bag");
  {
    std::ifstream in(file, std::ios::binary);
    const std::vector<char> bytes(std::istreambuf_iterator<char>(in), {});
    std::ofstream(cut, std::ios::binary)
        .write(bytes.data(), static_cast<std::streamsize>(bytes.size() / 2));
  }
  const Watchdog watchdog(kDeadline);
  std::size_t refused = 0;
  {
    const BusyThreads busy;
    for (int i = 0; i < kReads; ++i) {
      const std::vector<BagMessage> got = readBagMessages(file);
      ASSERT_EQ(got.size(), expected.size()) << "read " << i;
      for (std::size_t m = 0; m < got.size(); ++m) {
        ASSERT_EQ(got[m].data, expected[m].data) << "read " << i << ", message " << m;
        ASSERT_EQ(got[m].stamp_ns, expected[m].stamp_ns);
      }
      if (i % 4 == 0) {
        try {
          openBagReader(cut);
        } catch (const std::runtime_error&) {
          ++refused;
        }
      }
    }
    EXPECT_GT(busy.rounds(), static_cast<std::uint64_t>(kReads)) << "the threads did not run";
  }
  std::error_code ignored;
  fs::remove(cut, ignored);
  EXPECT_EQ(refused, static_cast<std::size_t>((kReads + 3) / 4));
}

}  // namespace
}  // namespace socc::sensors::bags
