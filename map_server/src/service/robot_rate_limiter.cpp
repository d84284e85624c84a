#include "robot_rate_limiter.hpp"

#include <algorithm>

namespace socc::service {

RobotRateLimiter::RobotRateLimiter(double rate, double burst, std::size_t max_clients)
    : rate_(rate),
      burst_(std::max(burst, 1.0)),
      max_clients_(std::max<std::size_t>(max_clients, 1)) {}

double RobotRateLimiter::refilled(const Bucket& bucket, Clock::time_point now) const {
  const double seconds = std::chrono::duration<double>(now - bucket.last).count();
  return std::min(burst_, bucket.tokens + std::max(seconds, 0.0) * rate_);
}

void RobotRateLimiter::forgetIdle(Clock::time_point now) {
  // A full bucket is the state a new client starts in: forgetting it changes nothing.
  for (auto it = buckets_.begin(); it != buckets_.end();)
    it = refilled(it->second, now) >= burst_ ? buckets_.erase(it) : std::next(it);
  if (buckets_.size() >= max_clients_) buckets_.clear();  // all busy: start everyone afresh
}

bool RobotRateLimiter::othersActive(const std::string& client, Clock::time_point now) const {
  constexpr auto kWindow = std::chrono::seconds(1);
  for (const auto& [id, bucket] : buckets_)
    if (id != client && now - bucket.last < kWindow) return true;
  return false;
}

bool RobotRateLimiter::admit(const std::string& client, Clock::time_point now) {
  if (rate_ <= 0.0) return true;
  auto it = buckets_.find(client);
  if (it == buckets_.end()) {
    if (buckets_.size() >= max_clients_) forgetIdle(now);
    it = buckets_.emplace(client, Bucket{burst_, now}).first;
  }
  Bucket& bucket = it->second;
  bucket.tokens = refilled(bucket, now);
  bucket.last = now;
  if (bucket.tokens >= 1.0) {
    bucket.tokens -= 1.0;
    return true;
  }
  return !othersActive(client, now);  // alone: nobody to be fair to
}

}  // namespace socc::service
