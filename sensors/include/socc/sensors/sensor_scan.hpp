#pragma once
// One sweep of a LiDAR as decoded from its packets or read from a point-cloud message: points
// in the sensor frame with their exact times. Every input (packet decoders, PointCloud2
// messages) produces this; odom_client, socc-lidar and socc-to-lcmlog consume it.
#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace socc::sensors {

struct SensorScan {
  // Time of the sweep's reference instant [ns, the recording's clock]: the time of its earliest
  // point. time[i] is relative to it, so every time is >= 0.
  std::int64_t stamp_ns = 0;
  std::int64_t seq = 0;                    // 0, 1, 2 ... in the order scans are produced
  std::vector<Eigen::Vector3f> points;     // sensor frame [m] (x forward, y left, z up)
  std::vector<float> intensity;            // empty, or per point (vendor units, e.g. 0..255)
  std::vector<float> time;                 // empty, or per point [s] relative to stamp_ns
  std::vector<std::uint16_t> ring;         // empty, or per point: laser / beam index
  std::vector<std::uint8_t> return_index;  // empty, or per point: 0 first/strongest, 1 second
  // False when the sweep does not cover a whole rotation (the first or last of a recording,
  // or one with lost packets beyond the decoder's tolerance).
  bool complete = true;
  std::string source;  // for messages: "pcap foo.pcap", "bag x.mcap /points"
  std::string frame_id;  // the points' frame as a PointCloud2 names it; empty for packets

  std::size_t size() const { return points.size(); }
};

/// Anything that yields scans: a decoder fed by a packet source, or a point-cloud topic.
class ScanStream {
 public:
  virtual ~ScanStream() = default;
  /// The next scan, or nullopt at the end. Throws std::runtime_error on unusable input.
  virtual std::optional<SensorScan> next() = 0;
  /// Counted problems so far (dropped packets, foreign packets, damaged records...), one line
  /// per kind; empty when none.
  virtual std::string problems() const { return {}; }
};

}  // namespace socc::sensors
