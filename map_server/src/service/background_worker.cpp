#include "background_worker.hpp"

#include <utility>

namespace socc::service {

BackgroundWorker::BackgroundWorker(std::size_t max_waiting)
    : max_waiting_(max_waiting), worker_([this] { loop(); }) {}

BackgroundWorker::~BackgroundWorker() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
    waiting_.clear();
  }
  cancelled_.store(true);
  wake_.notify_all();
  worker_.join();
}

bool BackgroundWorker::submit(Job job) {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (full()) return false;
    waiting_.push_back(std::move(job));
  }
  wake_.notify_one();
  return true;
}

bool BackgroundWorker::hasRoom() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return !full();
}

// A finished job whose continuation has not run counts as running: the bound is on the
// replies the owner still owes.
bool BackgroundWorker::full() const {
  return waiting_.size() + (running_ ? 1 : 0) + finished_.size() > max_waiting_;
}

std::size_t BackgroundWorker::runFinished() {
  std::vector<Continuation> done;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    done.swap(finished_);
  }
  for (const Continuation& next : done)
    if (next) next();
  return done.size();
}

std::size_t BackgroundWorker::outstanding() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return waiting_.size() + (running_ ? 1 : 0) + finished_.size();
}

void BackgroundWorker::loop() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    wake_.wait(lock, [this] { return stopping_ || !waiting_.empty(); });
    if (stopping_) return;
    Job job = std::move(waiting_.front());
    waiting_.pop_front();
    running_ = true;
    lock.unlock();
    Continuation next;
    try {
      next = job(cancelled_);
    } catch (...) {
      // Breaks the contract; the job is dropped rather than taking the server down.
    }
    lock.lock();
    running_ = false;
    if (!stopping_) finished_.push_back(std::move(next));
  }
}

}  // namespace socc::service
