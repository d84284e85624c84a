// Velodyne packets -> sweeps: the model is detected or checked from the first packets
// (velodyne_detection.hpp), every point gets its firing time from the manual's timing
// (velodyne_model.hpp) and its position from the calibration, and a sweep ends where the
// azimuth crosses SensorConfig::cut_azimuth_deg.
#include "velodyne_decoder.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <stdexcept>

#include "../packet_clock.hpp"
#include "../sweep_builder.hpp"
#include "velodyne_detection.hpp"
#include "velodyne_packet.hpp"

namespace socc::sensors::velodyne {
namespace {

constexpr std::size_t kDetectionPackets = 16;
constexpr double kHourUs = 3600e6;
constexpr double kMaxSweepNs = 2e9;  // a sweep longer than this: the sensor is not rotating
constexpr int kCrossingDrop = 9000;  // hundredths of a degree: a larger step back is a new turn

// One laser's calibration in the form the inner loop uses.
struct LaserTerms {
  float cos_vert = 1, sin_vert = 0, cos_rot = 1, sin_rot = 0;
  float dist = 0, vert_offset = 0, horiz_offset = 0;
  // HDL-64E: the distance correction along x (y) is slope_x * |x| + base_x, linear between the
  // manual's calibration distances 2.4 m (1.93 m) and 25.04 m.
  bool two_point = false;
  float slope_x = 0, base_x = 0, slope_y = 0, base_y = 0;
};

struct Trig {
  std::array<double, 36000> cos_az{}, sin_az{};
  Trig() {
    for (int i = 0; i < 36000; ++i) {
      cos_az[static_cast<std::size_t>(i)] = std::cos(i * M_PI / 18000.0);
      sin_az[static_cast<std::size_t>(i)] = std::sin(i * M_PI / 18000.0);
    }
  }
};

bool sameLaser(const LaserCalibration& a, const LaserCalibration& b) {
  return a.vert_rad == b.vert_rad && a.rot_rad == b.rot_rad && a.dist_m == b.dist_m &&
         a.vert_offset_m == b.vert_offset_m && a.horiz_offset_m == b.horiz_offset_m;
}

bool allZero(const LaserCalibration& l) {
  return l.vert_rad == 0 && l.rot_rad == 0 && l.dist_m == 0 && l.vert_offset_m == 0 &&
         l.horiz_offset_m == 0;
}

// A calibration file of another model is refused: too few lasers, extra lasers that are in use,
// or beam angles far from the model's nominal ones.
void checkCalibration(const ModelInfo& m, const Calibration& cal, const std::string& file) {
  const auto n = static_cast<std::size_t>(m.lasers);
  const std::string where = file.empty() ? std::string("nominal calibration") : file;
  if (cal.lasers.size() < n)
    throw std::runtime_error(where + ": " + std::to_string(cal.lasers.size()) + " lasers, a " +
                             std::string(m.name) + " has " + std::to_string(n) +
                             ": wrong calibration file?");
  for (std::size_t i = n; i < cal.lasers.size(); ++i) {
    const LaserCalibration& l = cal.lasers[i];
    if (l.enabled && !allZero(l) && !sameLaser(l, cal.lasers[i % n]))
      throw std::runtime_error(where + ": lists " + std::to_string(cal.lasers.size()) +
                               " lasers in use, a " + std::string(m.name) + " has " +
                               std::to_string(n) + ": wrong calibration file?");
  }
  for (std::size_t i = 0; i < m.vert_deg.size() && i < n; ++i) {
    const double deg = cal.lasers[i].vert_rad * 180.0 / M_PI;
    if (std::abs(deg - m.vert_deg[i]) > 2.0)
      throw std::runtime_error(where + ": laser " + std::to_string(i) + " points at " +
                               std::to_string(deg) + " deg elevation, a " + std::string(m.name) +
                               "'s at " + std::to_string(m.vert_deg[i]) +
                               " deg: a calibration of another model?");
  }
}

class VelodyneDecoder final : public ScanDecoder {
 public:
  explicit VelodyneDecoder(const SensorConfig& config)
      : config_(config), sweep_(config.keep_partial) {
    if (!config.model.empty()) {
      configured_ = findVelodyneModel(config.model);
      if (configured_ == nullptr) throw std::runtime_error("not a Velodyne model: " + config.model);
    }
    if (config.returns == ReturnMode::kFirst)
      throw std::runtime_error(
          "Velodyne sensors report the strongest and the last return, not the first");
    if (!config.calibration.empty()) calibration_ = loadCalibration(config.calibration);
    const double cut = std::fmod(std::fmod(config.cut_azimuth_deg, 360.0) + 360.0, 360.0);
    cut_ = static_cast<int>(std::lround(cut * 100.0)) % 36000;
    if (configured_ != nullptr && calibration_.lasers.empty())
      calibration_ = nominalCalibration(*configured_);
  }

  void feed(const Packet& packet, std::vector<SensorScan>& out) override {
    if (packet.data.size() != kPacketBytes) {
      ++stats_.foreign;  // position / telemetry packets, other devices
      return;
    }
    if (model_ == nullptr) {
      pending_.push_back(packet);
      if (pending_.size() >= kDetectionPackets) startDecoding(out);
      return;
    }
    decode(packet, out);
  }

  void flush(std::vector<SensorScan>& out) override {
    if (model_ == nullptr && !pending_.empty()) {
      if (pending_.size() < 2 && configured_ == nullptr)
        throw std::runtime_error(
            "too few Velodyne packets to detect the model; name it with --sensor");
      startDecoding(out);
    }
    if (clock_) sweep_.finish(false, clock_->offsetNs(), out, stats_);
  }

  const DecodeStats& stats() const override { return stats_; }
  std::string model() const override {
    if (model_ != nullptr) return std::string(model_->name);
    return configured_ != nullptr ? std::string(configured_->name)
                                  : std::string("velodyne (detecting)");
  }
  std::string notes() const override { return note_; }

 private:
  void startDecoding(std::vector<SensorScan>& out) {
    const Detection d = detectModel(pending_, configured_);
    model_ = d.model;
    dual_ = d.dual;
    note_ = d.note;
    if (calibration_.lasers.empty()) calibration_ = nominalCalibration(*model_);
    checkCalibration(*model_, calibration_, config_.calibration.string());
    resolution_ = calibration_.distance_resolution_m > 0.0 ? calibration_.distance_resolution_m
                                                           : model_->distance_resolution_m;
    layout_ = packetLayout(*model_, dual_);
    for (int b = 0; b < kBlocks; ++b)
      for (int c = 0; c < kChannels; ++c) {
        const float offset = layout_.slots[b][c].offset_us;
        since_block_start_us_[b][c] = offset - layout_.block_start_us[b];
        offset_ns_[b][c] = std::llround(static_cast<double>(offset) * 1000.0);
      }
    min_range_ = static_cast<float>(config_.min_range);
    max_range_ = config_.max_range > 0.0 ? static_cast<float>(config_.max_range) : 1e9f;
    buildLaserTerms();
    firing_step_us_ = layout_.packet_period_us;
    for (int b = 1; b < kBlocks; ++b)
      if (layout_.used[b] && layout_.block_start_us[b] != layout_.block_start_us[0]) {
        firing_step_us_ = layout_.block_start_us[b] - layout_.block_start_us[0];
        break;
      }
    clock_.emplace(kHourUs);
    std::vector<Packet> pending;
    pending.swap(pending_);
    for (const Packet& p : pending) decode(p, out);
  }

  void buildLaserTerms() {
    lasers_.clear();
    for (int i = 0; i < model_->lasers; ++i) {
      const LaserCalibration& c = calibration_.lasers[static_cast<std::size_t>(i)];
      LaserTerms t;
      t.cos_vert = static_cast<float>(std::cos(c.vert_rad));
      t.sin_vert = static_cast<float>(std::sin(c.vert_rad));
      t.cos_rot = static_cast<float>(std::cos(c.rot_rad));
      t.sin_rot = static_cast<float>(std::sin(c.rot_rad));
      t.dist = static_cast<float>(c.dist_m);
      t.slope_x = static_cast<float>((c.dist_m - c.dist_x_m) / (25.04 - 2.4));
      t.base_x = static_cast<float>(c.dist_x_m - c.dist_m) - 2.4f * t.slope_x;
      t.slope_y = static_cast<float>((c.dist_m - c.dist_y_m) / (25.04 - 1.93));
      t.base_y = static_cast<float>(c.dist_y_m - c.dist_m) - 1.93f * t.slope_y;
      t.vert_offset = static_cast<float>(c.vert_offset_m);
      t.horiz_offset = static_cast<float>(c.horiz_offset_m);
      t.two_point = c.dist_x_m != 0.0 || c.dist_y_m != 0.0;
      lasers_.push_back(t);
    }
  }

  // A packet is decoded only when every block it uses carries this model's flag and a valid
  // azimuth; a packet with the flags of another Velodyne layout is foreign.
  bool accept(const Packet& packet) {
    bool flags_known = true;
    bool flags_match = true;
    for (int b = 0; b < kBlocks; ++b) {
      if (!layout_.used[b]) continue;
      const std::uint16_t f = blockFlag(packet.data, b);
      flags_match = flags_match && f == layout_.flag[b];
      flags_known = flags_known && (f == 0xEEFF || f == 0xDDFF || f == 0xCCFF || f == 0xBBFF);
      if (blockAzimuth(packet.data, b) >= 36000) {
        ++stats_.malformed;
        return false;
      }
    }
    if (!flags_match) {
      ++(flags_known ? stats_.foreign : stats_.malformed);
      return false;
    }
    return true;
  }

  void finishSweep(bool complete, std::vector<SensorScan>& out) {
    const double tolerance_deg = 3.6;  // 1 % of a turn lost and the sweep is still whole
    const bool whole =
        complete && lost_deg_in_sweep_ <= std::max(tolerance_deg, packet_deg_ * 1.01);
    sweep_.finish(whole, clock_->offsetNs(), out, stats_);
    lost_deg_in_sweep_ = 0.0;
  }

  // Rotation speed [hundredths of a degree per us]: the median step between the packet's firing
  // sequences (a blind sector inside a packet is one outlier), or the step from the previous
  // packet when the packet holds one sequence (VLS-128 dual return).
  double rotationRate(const Packet& packet, std::int64_t sensor_ns, bool continuous) {
    std::array<double, kBlocks> rates{};
    std::size_t n = 0;
    int prev = -1;
    for (int b = 0; b < kBlocks; ++b) {
      if (!layout_.used[b]) continue;
      if (prev >= 0 && layout_.block_start_us[b] == layout_.block_start_us[prev]) continue;
      if (prev >= 0)
        rates[n++] = azimuthStep(blockAzimuth(packet.data, prev), blockAzimuth(packet.data, b)) /
                     static_cast<double>(layout_.block_start_us[b] - layout_.block_start_us[prev]);
      prev = b;
    }
    const int az0 = blockAzimuth(packet.data, 0);
    double rate = 0.0;
    if (n > 0) {
      std::nth_element(rates.begin(), rates.begin() + static_cast<std::ptrdiff_t>(n / 2),
                       rates.begin() + n);
      rate = rates[n / 2];
    } else if (continuous && prev_az_ >= 0) {
      const double dt_us = static_cast<double>(sensor_ns - prev_sensor_ns_) * 1e-3;
      if (dt_us > 0.0) rate = azimuthStep(prev_az_, az0) / dt_us;
    }
    prev_az_ = az0;
    prev_sensor_ns_ = sensor_ns;
    if (rate > 0.0 && rate < 1.0) rate_ = rate;  // up to 27 turns a second: plausible
    return rate_;
  }

  // Packets lost before this one, from the azimuth: the step from the previous packet's last
  // firing to this packet's first should be one firing's worth. (A time gap with a continuous
  // azimuth is a blind sector of a sensor with a restricted field of view, not a loss.)
  void countLost(const Packet& packet, double rate) {
    if (last_block_az_ < 0) return;
    const double expected = rate * firing_step_us_;
    const double excess = azimuthStep(last_block_az_, blockAzimuth(packet.data, 0)) - expected;
    const double per_packet = packet_deg_ * 100.0;
    if (per_packet <= 0.0 || excess < 0.5 * per_packet) return;
    const auto lost = static_cast<std::uint64_t>(std::llround(excess / per_packet));
    stats_.gaps += lost;
    lost_deg_in_sweep_ += static_cast<double>(lost) * packet_deg_;
  }

  void decode(const Packet& packet, std::vector<SensorScan>& out) {
    if (!accept(packet)) return;
    const PacketClock::Placement place =
        clock_->place(packetStamp(packet.data), packet.stamp_ns, layout_.firing_span_end_us);
    if (place.order == PacketClock::Order::kLate) {
      ++stats_.late;
      return;
    }
    if (place.order == PacketClock::Order::kRestart) {
      finishSweep(false, out);
      prev_rel_ = -1;
      last_block_az_ = -1;
      started_at_cut_ = false;
    }
    const double rate =
        rotationRate(packet, place.sensor_ns, place.order == PacketClock::Order::kNext);
    packet_deg_ = rate * layout_.packet_period_us / 100.0;
    if (place.order == PacketClock::Order::kNext) countLost(packet, rate);
    if (!reserved_ && packet_deg_ > 0.1) {  // room for a whole turn from the start
      const double points = 360.0 / packet_deg_ * kBlocks * kChannels * 1.1;
      sweep_.reserve(static_cast<std::size_t>(std::min(points, 4e6)));
      reserved_ = true;
    }
    if (!sweep_.empty() && static_cast<double>(place.sensor_ns - sweep_first_ns_) > kMaxSweepNs) {
      finishSweep(false, out);
      started_at_cut_ = false;
    }
    ++stats_.packets;
    const double rad_per_us = rate * M_PI / 18000.0;
    // A sensor with a restricted field of view fills a packet across its blind sector: blocks
    // after an azimuth jump fired that much later (the jump at the rotation speed).
    double blind_us = 0.0;
    int prev = -1;
    for (int b = 0; b < kBlocks; ++b) {
      if (!layout_.used[b]) continue;
      const int az = blockAzimuth(packet.data, b);
      if (prev >= 0 && layout_.block_start_us[b] != layout_.block_start_us[prev]) {
        const double expected = rate * (layout_.block_start_us[b] - layout_.block_start_us[prev]);
        const double actual = azimuthStep(blockAzimuth(packet.data, prev), az);
        if (actual > 3.0 * expected + 100.0) blind_us += (actual - expected) / rate;
      }
      prev = b;
      last_block_az_ = az;
      const int partner = layout_.partner[b];
      if (dual_ && partner > b) continue;  // decoded with its partner, the later of the two
      crossCut(az, out);
      const std::int64_t block_ns = place.sensor_ns + std::llround(blind_us * 1000.0);
      if (sweep_.empty()) sweep_first_ns_ = block_ns;
      if (!dual_) {
        decodeBlock(packet, b, block_ns, rad_per_us, 0);
      } else if (partner >= 0) {
        const bool last = layout_.return_slot[b] == 1;
        decodePair(packet, last ? b : partner, last ? partner : b, block_ns, rad_per_us);
      }
    }
  }

  void crossCut(int azimuth, std::vector<SensorScan>& out) {
    const int rel = azimuthStep(cut_, azimuth);
    if (prev_rel_ >= 0 && prev_rel_ - rel > kCrossingDrop) {
      finishSweep(started_at_cut_, out);
      started_at_cut_ = true;
    }
    prev_rel_ = rel;
  }

  struct Return {
    std::uint16_t raw;
    std::uint8_t reflectivity;
  };
  static Return readReturn(const Packet& p, int block, int channel) {
    const std::uint8_t* q = blockAt(p.data, block) + 4 + 3 * channel;
    return {readU16(q), q[2]};
  }

  // Dual return: block `last` holds the last return, `strongest` the strongest (or the second
  // strongest when the strongest is also the last); identical returns are one echo. The
  // selections go by what the returns are (the last is the farther echo, the strongest the
  // brighter), so they hold whichever block of a pair the firmware fills with which return.
  void decodePair(const Packet& p, int last, int strongest, std::int64_t stamp_ns,
                  double rad_per_us) {
    const BlockFrame fl = blockFrame(p, last, stamp_ns, rad_per_us);
    const BlockFrame fs = blockFrame(p, strongest, stamp_ns, rad_per_us);
    for (int c = 0; c < kChannels; ++c) {
      const Return l = readReturn(p, last, c);
      const Return s = readReturn(p, strongest, c);
      switch (config_.returns) {
        case ReturnMode::kLast:
          if (l.raw >= s.raw)
            emit(fl, c, l, 0);
          else
            emit(fs, c, s, 0);
          break;
        case ReturnMode::kStrongest:
          if (l.reflectivity >= s.reflectivity)
            emit(fl, c, l, 0);
          else
            emit(fs, c, s, 0);
          break;
        default:
          emit(fs, c, s, 0);
          if (l.raw != s.raw || l.reflectivity != s.reflectivity) emit(fl, c, l, 1);
          break;
      }
    }
  }

  void decodeBlock(const Packet& p, int b, std::int64_t stamp_ns, double rad_per_us,
                   std::uint8_t ret) {
    const BlockFrame f = blockFrame(p, b, stamp_ns, rad_per_us);
    for (int c = 0; c < kChannels; ++c) emit(f, c, readReturn(p, b, c), ret);
  }

  // What every point of one block shares: its azimuth's cos / sin, the packet's sensor time.
  struct BlockFrame {
    int block = 0;
    double cos_az = 1.0, sin_az = 0.0;
    std::int64_t stamp_ns = 0;
    double rad_per_us = 0.0;
  };
  BlockFrame blockFrame(const Packet& p, int b, std::int64_t stamp_ns, double rad_per_us) const {
    const auto az = static_cast<std::size_t>(blockAzimuth(p.data, b));
    return {b, trig_.cos_az[az], trig_.sin_az[az], stamp_ns, rad_per_us};
  }

  void emit(const BlockFrame& f, int c, Return r, std::uint8_t return_index) {
    if (r.raw == 0) return;  // no echo
    const PointSlot& slot = layout_.slots[f.block][c];
    const LaserTerms& l = lasers_[slot.laser];
    const float distance = static_cast<float>(r.raw * resolution_) + l.dist;
    if (distance < min_range_ || distance > max_range_ || distance <= 0.0f) return;
    // Azimuth at the firing: the block's azimuth advanced by the rotation since the sequence
    // start, then the laser's azimuth offset (cos/sin by angle sums, no trig in the loop).
    const double d = f.rad_per_us * since_block_start_us_[f.block][c];
    const double d2 = d * d;
    const double cd = 1.0 - d2 * (0.5 - d2 / 24.0);
    const double sd = d * (1.0 - d2 / 6.0);
    const double ca = f.cos_az * cd - f.sin_az * sd;
    const double sa = f.sin_az * cd + f.cos_az * sd;
    const float cos_az = static_cast<float>(ca * l.cos_rot + sa * l.sin_rot);
    const float sin_az = static_cast<float>(sa * l.cos_rot - ca * l.sin_rot);
    const float xy = distance * l.cos_vert - l.vert_offset * l.sin_vert;
    // Velodyne frame: y forward at azimuth 0, x to the right, azimuth clockwise from above.
    float xv = xy * sin_az - l.horiz_offset * cos_az;
    float yv = xy * cos_az + l.horiz_offset * sin_az;
    if (l.two_point) twoPoint(l, cos_az, sin_az, xv, yv);
    const float z = distance * l.sin_vert + l.vert_offset * l.cos_vert;
    // socc's sensor frame: x forward, y left, z up.
    sweep_.add(Eigen::Vector3f(yv, -xv, z), static_cast<float>(r.reflectivity),
               f.stamp_ns + offset_ns_[f.block][c], slot.laser, return_index);
  }

  // HDL-64E calibration: the distance correction varies linearly along x and y (LaserTerms);
  // the corrected distance moves the point along the beam's horizontal direction.
  static void twoPoint(const LaserTerms& l, float cos_az, float sin_az, float& xv, float& yv) {
    const float corr_x = l.slope_x * std::abs(xv) + l.base_x;
    const float corr_y = l.slope_y * std::abs(yv) + l.base_y;
    xv += corr_x * l.cos_vert * sin_az;
    yv += corr_y * l.cos_vert * cos_az;
  }

  SensorConfig config_;
  const ModelInfo* configured_ = nullptr;
  const ModelInfo* model_ = nullptr;
  bool dual_ = false;
  std::string note_;
  Calibration calibration_;
  double resolution_ = 0.002;
  PacketLayout layout_;
  // Per data point of a packet: its firing time after its block's sequence start [us] and after
  // the packet's stamp [ns] (the manual's timing, precomputed).
  std::array<std::array<float, kChannels>, kBlocks> since_block_start_us_{};
  std::array<std::array<std::int64_t, kChannels>, kBlocks> offset_ns_{};
  bool reserved_ = false;
  float min_range_ = 0.0f;
  float max_range_ = 0.0f;
  std::vector<LaserTerms> lasers_;
  std::vector<Packet> pending_;
  std::optional<PacketClock> clock_;
  SweepBuilder sweep_;
  Trig trig_;
  int cut_ = 0;
  int prev_rel_ = -1;
  bool started_at_cut_ = false;
  double lost_deg_in_sweep_ = 0.0;
  double packet_deg_ = 0.0;
  double rate_ = 36000.0 / 1e5;  // hundredths of a degree per us at 10 Hz until measured
  double firing_step_us_ = 0.0;  // between consecutive firing sequences
  int last_block_az_ = -1;       // the previous packet's last firing
  int prev_az_ = -1;
  std::int64_t prev_sensor_ns_ = 0;
  std::int64_t sweep_first_ns_ = 0;
  DecodeStats stats_;
};

}  // namespace

std::unique_ptr<ScanDecoder> makeVelodyneDecoder(const SensorConfig& config) {
  return std::make_unique<VelodyneDecoder>(config);
}

}  // namespace socc::sensors::velodyne
