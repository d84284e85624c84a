#pragma once
// One persistent thread for long jobs the LCM thread must not wait for (the LOCALIZE search,
// docs/relocalization.md "Threading"). Jobs run one at a time in submission order; each returns
// a continuation that the owner runs on its own thread (runFinished(), polled), so whatever a
// job's result touches (the grid, LCM) stays on the owner's thread. At most max_waiting jobs
// wait behind the one under way (running, or finished with its continuation not run yet). The
// destructor cancels the running job (its flag), drops the waiting and finished ones without
// running them, and joins.
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace socc::service {

class BackgroundWorker {
 public:
  /// Runs on the owner's thread, after its job.
  using Continuation = std::function<void()>;
  /// Runs on the worker; should return soon once cancelled becomes true. Must not throw.
  using Job = std::function<Continuation(const std::atomic<bool>& cancelled)>;

  explicit BackgroundWorker(std::size_t max_waiting);
  ~BackgroundWorker();
  BackgroundWorker(const BackgroundWorker&) = delete;
  BackgroundWorker& operator=(const BackgroundWorker&) = delete;

  /// False (job dropped) when max_waiting jobs wait already.
  bool submit(Job job);
  /// Whether submit() would take a job now (only the owner submits: stays true until it does).
  bool hasRoom() const;
  /// Runs the continuations of the jobs finished so far, in order; returns how many ran.
  std::size_t runFinished();
  /// Jobs submitted whose continuation has not run yet.
  std::size_t outstanding() const;

 private:
  void loop();
  bool full() const;  // mutex_ held

  const std::size_t max_waiting_;
  mutable std::mutex mutex_;  // guards everything below but cancelled_ and worker_
  std::condition_variable wake_;
  std::deque<Job> waiting_;
  bool running_ = false;
  std::vector<Continuation> finished_;
  bool stopping_ = false;
  std::atomic<bool> cancelled_{false};
  std::thread worker_;  // last: started once everything it uses exists
};

}  // namespace socc::service
