// Ouster packets -> frames: a frame is the sensor's own (frame id), complete when every column
// of the column window arrived; a point's time is its column's timestamp.
#include "socc/sensors/ouster_decoder.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <optional>
#include <stdexcept>

#include "ouster_layout.hpp"
#include "ouster_metadata.hpp"
#include "packet_bytes.hpp"
#include "sweep_builder.hpp"

namespace socc::sensors {
namespace {

constexpr double kOusterPi = 3.14159265358979323846;
// Lidar packets that do not fit the metadata before any that does: the metadata is wrong.
constexpr std::uint64_t kOusterMismatchBeforeRefusal = 50;
constexpr std::size_t kOusterImuPacketSize = 48;  // the sensor's other packets, on their own port
// Closer than this is the sensor's own housing / window, not a return (Ouster's datasheets
// give 0.3 m as the minimum range of OS0 / OS1 / OS2... the smallest figure is used).
constexpr double kOusterMinRange = 0.25;

// Per column and beam: point = range * direction + offset, in the sensor frame [m].
class OusterLut {
 public:
  explicit OusterLut(const OusterMetadata& md) : beams_(md.pixels_per_column) {
    const Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>> l2s(
        md.lidar_to_sensor.data());
    const Eigen::Matrix3d rotation = l2s.topLeftCorner<3, 3>();
    const Eigen::Vector3d translation = l2s.topRightCorner<3, 1>() * 1e-3;
    const double b03 = md.beam_to_lidar[3], b23 = md.beam_to_lidar[11];
    const double n = std::hypot(b03, b23);  // lidar origin to beam origin [mm]
    const int width = md.columns_per_frame;
    direction_.resize(static_cast<std::size_t>(width * beams_));
    offset_.resize(direction_.size());
    for (int m = 0; m < width; ++m) {
      const double encoder = 2.0 * kOusterPi * (1.0 - static_cast<double>(m) / width);
      for (int b = 0; b < beams_; ++b) {
        const double azimuth =
            -2.0 * kOusterPi * md.beam_azimuth_deg[static_cast<std::size_t>(b)] / 360.0;
        const double altitude =
            2.0 * kOusterPi * md.beam_altitude_deg[static_cast<std::size_t>(b)] / 360.0;
        const Eigen::Vector3d dir(std::cos(encoder + azimuth) * std::cos(altitude),
                                  std::sin(encoder + azimuth) * std::cos(altitude),
                                  std::sin(altitude));
        const Eigen::Vector3d offset_mm(b03 * std::cos(encoder) - n * dir.x(),
                                        b03 * std::sin(encoder) - n * dir.y(), b23 - n * dir.z());
        const auto i = index(m, b);
        direction_[i] = (rotation * dir).cast<float>();
        offset_[i] = (rotation * offset_mm * 1e-3 + translation).cast<float>();
      }
    }
  }
  Eigen::Vector3f point(int column, int beam, double range_m) const {
    const auto i = index(column, beam);
    return direction_[i] * static_cast<float>(range_m) + offset_[i];
  }

 private:
  std::size_t index(int column, int beam) const {
    return static_cast<std::size_t>(column) * static_cast<std::size_t>(beams_) +
           static_cast<std::size_t>(beam);
  }
  int beams_;
  std::vector<Eigen::Vector3f> direction_, offset_;
};

// A size some Ouster lidar or IMU packet has (any profile, beam count, 8 or 16 columns).
bool isOusterPacketSize(std::size_t size) {
  if (size == kOusterImuPacketSize) return true;
  for (const OusterProfile p : {OusterProfile::kLegacy, OusterProfile::kSingle,
                                OusterProfile::kLowData, OusterProfile::kDual})
    for (const int beams : {16, 32, 64, 128})
      for (const int columns : {8, 16})
        if (OusterLayout(p, beams, columns).packet_size == size) return true;
  return false;
}

class OusterDecoder final : public ScanDecoder {
 public:
  OusterDecoder(OusterMetadata md, const SensorConfig& config)
      : md_(std::move(md)),
        layout_(md_.profile, md_.pixels_per_column, md_.columns_per_packet),
        lut_(md_),
        config_(config),
        sweep_(config.keep_partial),
        received_(static_cast<std::size_t>(md_.columns_per_frame), false) {
    min_range_ = config.min_range > 0.0 ? config.min_range : kOusterMinRange;
    max_range_ = config.max_range > 0.0 ? config.max_range : 1e9;
  }

  void feed(const Packet& packet, std::vector<SensorScan>& out) override {
    const std::uint8_t* d = packet.data.data();
    if (packet.data.size() != layout_.packet_size) {
      // Another sensor's format or the IMU's packets; any other size is a damaged packet.
      (isOusterPacketSize(packet.data.size()) ? stats_.foreign : stats_.malformed)++;
      if (packet.data.size() != kOusterImuPacketSize)
        refuseIfOnlyMismatch(std::to_string(packet.data.size()) + " B packets, the metadata's " +
                             md_.profile_name + " format with " +
                             std::to_string(md_.pixels_per_column) + " beams and " +
                             std::to_string(md_.columns_per_packet) + " columns a packet has " +
                             std::to_string(layout_.packet_size) + " B");
      return;
    }
    if (md_.profile != OusterProfile::kLegacy) {
      const std::uint32_t init_id = packet_bytes::u32(d + 4) & 0xffffffu;
      const std::uint64_t serial = packet_bytes::u64(d + 7) & 0xffffffffffULL;
      if (packet_bytes::u16(d) != 1 || (md_.init_id && init_id != md_.init_id) ||
          (md_.serial && serial != md_.serial)) {
        ++stats_.foreign;
        refuseIfOnlyMismatch("packets of sensor " + std::to_string(serial) + " (init id " +
                             std::to_string(init_id) + "), the metadata is for sensor " +
                             std::to_string(md_.serial) + " (init id " +
                             std::to_string(md_.init_id) + ")");
        return;
      }
    }
    if (!columnsWellFormed(d)) {
      ++stats_.malformed;
      return;
    }
    const std::uint16_t frame = layout_.frameId(d);
    if (frame_) {
      const int age = static_cast<std::uint16_t>(*frame_ - frame);
      if (frame != *frame_ && age < 0x8000) {  // an older frame: reordered or duplicated
        ++stats_.late;
        return;
      }
      if (frame == *frame_ && emitted_) {  // its frame was already complete and emitted
        ++stats_.late;
        return;
      }
      if (frame != *frame_) startFrame(out, false);
    }
    if (!frame_) {
      frame_ = frame;
      emitted_ = false;
    }
    const auto* last = layout_.column(d, md_.columns_per_packet - 1);
    sweep_.fixClockOffset(
        clockOffset(packet.stamp_ns, static_cast<std::int64_t>(layout_.timestamp(last))));
    ++stats_.packets;
    for (int c = 0; c < md_.columns_per_packet; ++c) decodeColumn(layout_.column(d, c));
    if (received_count_ == md_.windowColumns()) {
      finishFrame(out, true, false);
      emitted_ = true;
    }
  }

  void flush(std::vector<SensorScan>& out) override {
    if (frame_ && !emitted_) finishFrame(out, received_count_ == md_.windowColumns(), true);
    frame_.reset();
    first_frame_ = true;
  }

  const DecodeStats& stats() const override { return stats_; }
  std::string model() const override { return md_.model; }

 private:
  void refuseIfOnlyMismatch(const std::string& what) {
    if (stats_.packets > 0 || ++mismatches_ < kOusterMismatchBeforeRefusal) return;
    throw std::runtime_error("the Ouster packets do not fit the metadata: " + what +
                             " (is the metadata JSON the one of this recording?)");
  }

  // Measurement ids in the frame, timestamps never decreasing: else the packet is damaged.
  bool columnsWellFormed(const std::uint8_t* d) const {
    std::uint64_t previous = 0;
    for (int c = 0; c < md_.columns_per_packet; ++c) {
      const std::uint8_t* col = layout_.column(d, c);
      if (!layout_.valid(col)) continue;
      if (layout_.measurementId(col) >= md_.columns_per_frame) return false;
      const std::uint64_t t = layout_.timestamp(col);
      if (t < previous) return false;
      previous = t;
    }
    return true;
  }

  void decodeColumn(const std::uint8_t* col) {
    if (!layout_.valid(col)) return;
    const int m = layout_.measurementId(col);
    if (!md_.inWindow(m) || received_[static_cast<std::size_t>(m)]) return;
    received_[static_cast<std::size_t>(m)] = true;
    ++received_count_;
    const auto time_ns = static_cast<std::int64_t>(layout_.timestamp(col));
    for (int b = 0; b < md_.pixels_per_column; ++b) {
      OusterReturn r[2];
      const int n = ousterReturns(md_.profile, layout_.pixel(col, b), r);
      for (int k = 0; k < n; ++k) {
        if (n == 2 && !wanted(r, k)) continue;
        const double range = r[k].range_mm * 1e-3;
        if (r[k].range_mm == 0 || range < min_range_ || range > max_range_) continue;
        sweep_.add(lut_.point(m, b, range), r[k].reflectivity, time_ns,
                   static_cast<std::uint16_t>(b), static_cast<std::uint8_t>(k));
      }
    }
  }

  // Dual profile: return 0 is the strongest, 1 the second strongest (0 range: none).
  bool wanted(const OusterReturn* r, int k) const {
    const bool other_missing = r[1 - k].range_mm == 0;
    switch (config_.returns) {
      case ReturnMode::kAll:
        return true;
      case ReturnMode::kStrongest:
        return k == 0;
      case ReturnMode::kFirst:
        return other_missing || r[k].range_mm <= r[1 - k].range_mm;
      case ReturnMode::kLast:
        return other_missing || r[k].range_mm > r[1 - k].range_mm;
    }
    return true;
  }

  void startFrame(std::vector<SensorScan>& out, bool at_end) {
    if (!emitted_) finishFrame(out, received_count_ == md_.windowColumns(), at_end);
    frame_.reset();
  }

  void finishFrame(std::vector<SensorScan>& out, bool complete, bool at_end) {
    // Lost packets inside the recording (not before its first or after its last packet).
    if (!complete && !first_frame_ && !at_end) {
      const int missing = md_.windowColumns() - received_count_;
      stats_.gaps += static_cast<std::uint64_t>((missing + md_.columns_per_packet - 1) /
                                                md_.columns_per_packet);
    }
    sweep_.finish(complete, out, stats_);
    std::fill(received_.begin(), received_.end(), false);
    received_count_ = 0;
    first_frame_ = false;
  }

  OusterMetadata md_;
  OusterLayout layout_;
  OusterLut lut_;
  SensorConfig config_;
  double min_range_ = 0.0, max_range_ = 0.0;
  SweepBuilder sweep_;
  DecodeStats stats_;
  std::optional<std::uint16_t> frame_;
  bool emitted_ = false;
  bool first_frame_ = true;
  std::vector<bool> received_;
  int received_count_ = 0;
  std::uint64_t mismatches_ = 0;
};

}  // namespace

bool isOusterModel(const std::string& model) {
  return model == "ouster" || (!model.empty() && ousterModelName(model) == model);
}

std::unique_ptr<ScanDecoder> makeOusterDecoder(const SensorConfig& config) {
  if (config.calibration.empty())
    throw std::runtime_error(
        "an Ouster sensor needs its metadata JSON (--calibration FILE: the sensor's "
        "/api/v1/sensor/metadata, or the .json saved with the recording)");
  OusterMetadata md = readOusterMetadata(config.calibration);
  if (!config.model.empty() && config.model != "ouster" && config.model != md.model)
    throw std::runtime_error("the sensor was configured as " + config.model + " but " +
                             config.calibration.string() + " is the metadata of an " +
                             md.prod_line + " (" + md.model + ")");
  return std::make_unique<OusterDecoder>(std::move(md), config);
}

}  // namespace socc::sensors
