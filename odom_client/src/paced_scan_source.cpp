// Files replayed at the pace of their time stamps (scan_source.hpp atRecordedPace): each scan
// is handed out no earlier than its time after the first scan's, divided by the rate, so that
// what runs beside the scan loop (the map server's consistency service, other robots) sees the
// robot at the speed it drove, not at the speed the odometry can read files.
#include <chrono>
#include <cstdio>
#include <iostream>
#include <stdexcept>
#include <string>
#include <thread>

#include "socc/odom/scan_source.hpp"

namespace socc::odom {
namespace {

using Clock = std::chrono::steady_clock;

class PacedScanSource final : public ScanSource {
 public:
  PacedScanSource(std::unique_ptr<ScanSource> source, double rate)
      : source_(std::move(source)), rate_(rate) {
    if (!(rate > 0.0)) throw std::invalid_argument("the replay rate must be > 0");
  }
  ~PacedScanSource() override { report(); }

  std::optional<Scan> next() override {
    std::optional<Scan> scan = source_->next();
    if (!scan) {
      report();
      return scan;
    }
    waitUntilDue(scan->utime);
    return scan;
  }

  std::size_t remaining() const override { return source_->remaining(); }
  std::string timing() const override { return source_->timing(); }
  // Scans come at the sensor's pace whether or not the loop is ready for them.
  bool live() const override { return true; }

 private:
  void waitUntilDue(std::int64_t utime) {
    const Clock::time_point now = Clock::now();
    if (!first_utime_) {
      first_utime_ = utime;
      start_ = now;
    }
    const auto offset =
        std::chrono::duration<double>(static_cast<double>(utime - *first_utime_) * 1e-6 / rate_);
    const Clock::time_point due = start_ + std::chrono::duration_cast<Clock::duration>(offset);
    if (now < due) {
      std::this_thread::sleep_until(due);
      return;
    }
    // Behind the recording: the scan is taken late rather than dropped (the input stays the
    // same), and the delay is reported at the end.
    const double late = std::chrono::duration<double>(now - due).count();
    if (late > kLateAfter) ++late_;
    if (late > max_late_) max_late_ = late;
  }

  void report() {
    if (late_ == 0 || reported_) return;
    reported_ = true;
    char text[160];
    std::snprintf(text, sizeof text,
                  "odom_client: replay at %gx the recorded pace: %zu scans taken late (up to "
                  "%.2f s behind the recording)\n",
                  rate_, late_, max_late_);
    std::cerr << text;
  }

  static constexpr double kLateAfter = 0.01;  // [s] below this, scheduling noise
  std::unique_ptr<ScanSource> source_;
  double rate_;
  std::optional<std::int64_t> first_utime_;
  Clock::time_point start_;
  std::size_t late_ = 0;
  double max_late_ = 0.0;
  bool reported_ = false;
};

}  // namespace

std::unique_ptr<ScanSource> atRecordedPace(std::unique_ptr<ScanSource> source, double rate) {
  return std::make_unique<PacedScanSource>(std::move(source), rate);
}

}  // namespace socc::odom
