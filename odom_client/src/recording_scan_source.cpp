// Recordings (pcap captures of LiDAR packets, ROS bags) as odometry input: every sweep that
// socc_sensors decodes or reads, with its exact per-point times. No labels: a raw sensor has none.
#include <iostream>

#include "socc/odom/scan_source.hpp"

namespace socc::odom {
namespace {

class RecordingScanSource final : public ScanSource {
 public:
  RecordingScanSource(const std::filesystem::path& file, const sensors::RecordingOptions& options,
                      FrameRange range)
      : stream_(sensors::openRecording(file, options)),
        range_(range),
        name_(file.filename().string()) {}

  std::optional<Scan> next() override {
    while (!ended_) {
      std::optional<sensors::SensorScan> sweep = stream_->next();
      if (!sweep || (range_.last >= 0 && sweep->seq > range_.last)) {
        finish();
        break;
      }
      if (sweep->seq < range_.first) continue;
      return toScan(std::move(*sweep));
    }
    return std::nullopt;
  }

  std::size_t remaining() const override { return 0; }  // unknown until the recording is read

 private:
  Scan toScan(sensors::SensorScan&& sweep) const {
    Scan scan;
    // utime in whole microseconds; the remainder moves into the point times, which stay exact.
    scan.utime = sweep.stamp_ns / 1000;
    const float remainder_s = static_cast<float>(sweep.stamp_ns - scan.utime * 1000) * 1e-9f;
    scan.seq = sweep.seq;
    scan.name = name_ + " sweep " + std::to_string(sweep.seq);
    scan.frame_id = std::move(sweep.frame_id);
    scan.cloud.points = std::move(sweep.points);
    scan.cloud.times = std::move(sweep.time);
    for (float& t : scan.cloud.times) t += remainder_s;
    return scan;
  }

  void finish() {
    ended_ = true;
    const std::string problems = stream_->problems();
    if (!problems.empty()) std::cerr << "odom_client: " << name_ << ":\n" << problems;
  }

  std::unique_ptr<sensors::ScanStream> stream_;
  FrameRange range_;
  std::string name_;
  bool ended_ = false;
};

}  // namespace

std::unique_ptr<ScanSource> openRecordingScans(const std::filesystem::path& file,
                                               const sensors::RecordingOptions& options,
                                               FrameRange range) {
  return std::make_unique<RecordingScanSource>(file, options, range);
}

}  // namespace socc::odom
