#include "socc/tools/latency_stats.hpp"

#include <algorithm>
#include <cmath>

namespace socc::tools {

void CallStats::recordOk(double latency_ms, int attempts) {
  latencies_ms_.push_back(latency_ms);
  retries_ += std::max(0, attempts - 1);
}

void CallStats::recordFailure(bool timed_out, int attempts) {
  ++failures_;
  retries_ += std::max(0, attempts - 1);
  if (timed_out)
    ++timeouts_;
  else
    ++errors_;
}

void CallStats::merge(const CallStats& other) {
  latencies_ms_.insert(latencies_ms_.end(), other.latencies_ms_.begin(), other.latencies_ms_.end());
  failures_ += other.failures_;
  timeouts_ += other.timeouts_;
  retries_ += other.retries_;
  errors_ += other.errors_;
}

LatencySummary CallStats::summary() const {
  std::vector<double> sorted = latencies_ms_;
  std::sort(sorted.begin(), sorted.end());
  LatencySummary s;
  s.p50_ms = percentile(sorted, 0.50);
  s.p90_ms = percentile(sorted, 0.90);
  s.p99_ms = percentile(sorted, 0.99);
  s.max_ms = sorted.empty() ? 0.0 : sorted.back();
  return s;
}

double percentile(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return 0.0;
  // Nearest rank: the smallest value with at least q of the samples at or below it.
  const auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(sorted.size())));
  return sorted[std::clamp<std::size_t>(rank, 1, sorted.size()) - 1];
}

}  // namespace socc::tools
