#pragma once
// Per-request-type counters of a load test: latencies of successful calls (end to end,
// including retries) plus timeouts, retries and error replies. Each robot thread owns its own
// CallStats and they are merged after the threads are joined, so no locking is needed.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace socc::tools {

struct LatencySummary {
  double p50_ms = 0, p90_ms = 0, p99_ms = 0, max_ms = 0;
};

class CallStats {
 public:
  void recordOk(double latency_ms, int attempts);
  void recordFailure(bool timed_out, int attempts);
  void merge(const CallStats& other);

  std::size_t calls() const { return latencies_ms_.size() + failures_; }
  std::size_t succeeded() const { return latencies_ms_.size(); }
  std::int64_t timeouts() const { return timeouts_; }
  std::int64_t retries() const { return retries_; }
  std::int64_t errors() const { return errors_; }
  /// Nearest-rank percentiles of the successful calls (all zero when there are none).
  LatencySummary summary() const;

 private:
  std::vector<double> latencies_ms_;
  std::size_t failures_ = 0;
  std::int64_t timeouts_ = 0;  // calls that got no reply after all attempts
  std::int64_t retries_ = 0;   // extra attempts (each one follows an attempt that timed out)
  std::int64_t errors_ = 0;    // calls answered with a non-OK status
};

/// Nearest-rank percentile (q in [0, 1]) of an ascending vector; 0 for an empty one.
double percentile(const std::vector<double>& sorted, double q);

}  // namespace socc::tools
