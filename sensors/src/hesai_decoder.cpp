// Hesai packets -> sweeps: one firing round (1 block, or 2 in dual-return mode) at a time,
// cut where the block azimuth crosses config.cut_azimuth_deg.
#include "socc/sensors/hesai_decoder.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include "hesai_calibration.hpp"
#include "hesai_layout.hpp"
#include "packet_bytes.hpp"
#include "sweep_builder.hpp"

namespace socc::sensors {
namespace {

constexpr double kHesaiDegToRad = 3.14159265358979323846 / 180.0;
// Packets of another model before any packet of the configured one: the configuration is wrong.
constexpr std::uint64_t kHesaiForeignBeforeRefusal = 50;
// A sweep missing up to this much azimuth (lost packets) still counts as complete.
constexpr double kHesaiMaxMissingDeg = 2.0;
// A jump of the sensor's clock beyond this ends the sweep (a restart, a long outage).
constexpr std::int64_t kHesaiMaxTimeJumpNs = 500'000'000;

class HesaiDecoder final : public ScanDecoder {
 public:
  HesaiDecoder(const HesaiLayout& layout, const HesaiCalibration& calibration,
               const SensorConfig& config)
      : layout_(layout), config_(config), sweep_(config.keep_partial) {
    for (int c = 0; c < layout.lasers; ++c) {
      const double el = calibration.elevation_deg[static_cast<std::size_t>(c)] * kHesaiDegToRad;
      cos_el_.push_back(std::cos(el));
      sin_el_.push_back(std::sin(el));
      const double offset =
          calibration.azimuth_offset_deg[static_cast<std::size_t>(c)] * kHesaiDegToRad;
      cos_offset_.push_back(std::cos(offset));
      sin_offset_.push_back(std::sin(offset));
    }
    for (int returns = 1; returns <= 2; ++returns)
      for (int b = 0; b < layout.blocks; ++b)
        for (int c = 0; c < layout.lasers; ++c)
          offset_ns_[returns - 1].push_back(layout.pointOffsetNs(b, c, returns));
    min_range_ = config.min_range > 0.0 ? config.min_range : layout.min_range;
    max_range_ = config.max_range > 0.0 ? config.max_range : layout.max_range;
    cut_ = static_cast<int>(std::lround(
               std::fmod(std::fmod(config.cut_azimuth_deg, 360.0) + 360.0, 360.0) * 100.0)) %
           36000;
  }

  void feed(const Packet& packet, std::vector<SensorScan>& out) override {
    HesaiPacket p;
    std::string why;
    const HesaiCheck check =
        parseHesaiPacket(layout_, packet.data.data(), packet.data.size(), p, why);
    if (check != HesaiCheck::kOk) {
      (check == HesaiCheck::kForeign ? stats_.foreign : stats_.malformed)++;
      refuseIfOnlyForeign(packet, why);
      return;
    }
    if (last_time_ns_ && p.time_ns <= *last_time_ns_) {
      ++stats_.late;
      return;
    }
    if (last_time_ns_ && p.time_ns - *last_time_ns_ > kHesaiMaxTimeJumpNs) {
      finishSweep(false, out);
      last_azimuth_.reset();
      started_at_cut_ = false;
    }
    last_time_ns_ = p.time_ns;
    ++stats_.packets;
    sweep_.fixClockOffset(clockOffset(packet.stamp_ns, p.time_ns));
    const int rounds = layout_.blocks / p.returns;
    const int round_step =
        rounds >= 2 ? azimuthStep(hesaiBlockAzimuth(layout_, packet.data.data(), 0),
                                  hesaiBlockAzimuth(layout_, packet.data.data(), p.returns))
                    : 0;
    for (int block = 0; block < layout_.blocks; block += p.returns) {
      const std::uint16_t azimuth = hesaiBlockAzimuth(layout_, packet.data.data(), block);
      if (last_azimuth_) {
        const int step = azimuthStep(*last_azimuth_, azimuth);
        if (round_step > 0 && step > 2 * round_step + 2) {
          missing_deg_ += (step - round_step) / 100.0;
          const long lost =
              std::lround(static_cast<double>(step - round_step) / round_step / rounds);
          stats_.gaps += static_cast<std::uint64_t>(std::max(1L, lost));
        }
        if (relative(azimuth) < relative(*last_azimuth_)) {
          finishSweep(started_at_cut_ && missing_deg_ <= kHesaiMaxMissingDeg, out);
          started_at_cut_ = true;
          sweep_.fixClockOffset(clockOffset(packet.stamp_ns, p.time_ns));
        }
      }
      last_azimuth_ = azimuth;
      decodeRound(packet.data.data(), p, block, azimuth);
    }
  }

  void flush(std::vector<SensorScan>& out) override {
    finishSweep(false, out);
    last_azimuth_.reset();
    started_at_cut_ = false;
  }

  const DecodeStats& stats() const override { return stats_; }
  std::string model() const override { return layout_.model; }

 private:
  static int azimuthStep(int from, int to) { return (to - from + 36000) % 36000; }
  int relative(int azimuth) const { return (azimuth - cut_ + 36000) % 36000; }

  // Nothing but packets that are not this model's from the start: the configuration is wrong
  // (or the stream is not this sensor's); decoding none of them, say so.
  void refuseIfOnlyForeign(const Packet& packet, const std::string& why) {
    if (stats_.packets > 0) return;
    const std::string other = detectHesaiModel(packet.data.data(), packet.data.size());
    if (!other.empty() && other != layout_.model) ++foreign_models_;
    if (++undecodable_ < kHesaiForeignBeforeRefusal) return;
    if (foreign_models_ * 2 > undecodable_)
      throw std::runtime_error("the sensor was configured as " + layout_.model +
                               " but its packets are " + why + "; use --sensor " + other +
                               " with that model's calibration");
    throw std::runtime_error("none of the first " + std::to_string(undecodable_) +
                             " packets is a " + layout_.model + " packet (the last: " + why +
                             "): check --sensor and the port");
  }

  struct Return {
    const std::uint8_t* unit;
    double distance;
  };

  void decodeRound(const std::uint8_t* data, const HesaiPacket& p, int first_block,
                   std::uint16_t azimuth) {
    // One sine and cosine per round; each channel's offset is added by the angle-sum formulas.
    const double block_az = azimuth * 0.01 * kHesaiDegToRad;
    const Rotation round{std::cos(block_az), std::sin(block_az)};
    for (int c = 0; c < layout_.lasers; ++c) {
      Return r[2];
      for (int i = 0; i < p.returns; ++i) {
        const std::uint8_t* unit = hesaiUnit(layout_, data, first_block + i, c);
        r[i] = {unit, packet_bytes::u16(unit) * p.distance_unit_m};
      }
      const int returns = p.returns == 2 && r[1].distance == r[0].distance ? 1 : p.returns;
      // Dual: index 0 is the stronger return (ties: the nearer).
      int strong = 0;
      if (returns == 2 && (r[1].unit[2] > r[0].unit[2] ||
                           (r[1].unit[2] == r[0].unit[2] && r[1].distance < r[0].distance)))
        strong = 1;
      for (int k = 0; k < returns; ++k) {
        const int i = returns == 2 ? (k == 0 ? strong : 1 - strong) : 0;
        if (returns == 2 && !wanted(r, i)) continue;
        addPoint(r[i], c, round,
                 p.time_ns + offset_ns_[p.returns - 1][offsetIndex(first_block + i, c)],
                 static_cast<std::uint8_t>(k));
      }
    }
  }

  // Which return of a dual pair config.returns keeps.
  bool wanted(const Return* r, int i) const {
    switch (config_.returns) {
      case ReturnMode::kAll:
        return true;
      case ReturnMode::kStrongest:
        return r[i].unit[2] > r[1 - i].unit[2] || (r[i].unit[2] == r[1 - i].unit[2] && i == 0);
      case ReturnMode::kLast:
        return nearest(r, i) == false;
      case ReturnMode::kFirst:
        return nearest(r, i);
    }
    return true;
  }
  static bool nearest(const Return* r, int i) {
    // A zero distance is no return: the other one is then both first and last.
    if (r[1 - i].distance == 0.0) return true;
    return r[i].distance != 0.0 && r[i].distance <= r[1 - i].distance;
  }

  std::size_t offsetIndex(int block, int channel) const {
    return static_cast<std::size_t>(block * layout_.lasers + channel);
  }

  struct Rotation {
    double cos, sin;
  };

  void addPoint(const Return& r, int channel, const Rotation& round, std::int64_t time_ns,
                std::uint8_t return_index) {
    if (r.distance == 0.0 || r.distance < min_range_ || r.distance > max_range_) return;
    const auto ch = static_cast<std::size_t>(channel);
    const double cos_az = round.cos * cos_offset_[ch] - round.sin * sin_offset_[ch];
    const double sin_az = round.sin * cos_offset_[ch] + round.cos * sin_offset_[ch];
    const double horizontal = r.distance * cos_el_[ch];
    // Hesai's frame has y forward and x right, azimuth clockwise from y; ours x forward, y left.
    const Eigen::Vector3f point(static_cast<float>(horizontal * cos_az),
                                static_cast<float>(-horizontal * sin_az),
                                static_cast<float>(r.distance * sin_el_[ch]));
    sweep_.add(point, r.unit[2], time_ns, static_cast<std::uint16_t>(channel), return_index);
  }

  void finishSweep(bool complete, std::vector<SensorScan>& out) {
    sweep_.finish(complete, out, stats_);
    missing_deg_ = 0.0;
  }

  const HesaiLayout& layout_;
  SensorConfig config_;
  std::vector<double> cos_el_, sin_el_, cos_offset_, sin_offset_;
  // Firing time of block, channel relative to the packet time [ns], single and dual return.
  std::vector<std::int64_t> offset_ns_[2];
  double min_range_ = 0.0, max_range_ = 0.0;
  int cut_ = 0;  // [0.01 deg]
  SweepBuilder sweep_;
  DecodeStats stats_;
  std::optional<std::uint16_t> last_azimuth_;
  std::optional<std::int64_t> last_time_ns_;
  bool started_at_cut_ = false;
  double missing_deg_ = 0.0;
  std::uint64_t foreign_models_ = 0;  // of those, packets of another Hesai model
  std::uint64_t undecodable_ = 0;     // packets before the first decoded one
};

}  // namespace

std::vector<std::string> hesaiModels() {
  std::vector<std::string> models;
  for (const HesaiLayout& l : hesaiLayouts()) models.push_back(l.model);
  return models;
}

bool isHesaiModel(const std::string& model) {
  return hesaiLayout(model) != nullptr;
}

std::string detectHesaiModel(const std::vector<std::uint8_t>& payload) {
  return detectHesaiModel(payload.data(), payload.size());
}

std::unique_ptr<ScanDecoder> makeHesaiDecoder(const SensorConfig& config) {
  const HesaiLayout* layout = hesaiLayout(config.model);
  if (!layout) throw std::runtime_error("unknown Hesai model \"" + config.model + "\"");
  HesaiCalibration calibration;
  if (!config.calibration.empty()) {
    calibration = readHesaiCalibration(config.calibration, layout->lasers);
  } else if (!layout->nominal_elevation_deg.empty()) {
    calibration.elevation_deg = layout->nominal_elevation_deg;
    calibration.azimuth_offset_deg.assign(layout->nominal_elevation_deg.size(), 0.0f);
  } else {
    throw std::runtime_error(config.model +
                             " needs its angle-correction CSV (--calibration FILE): its beams "
                             "have no nominal angles to fall back to");
  }
  return std::make_unique<HesaiDecoder>(*layout, calibration, config);
}

}  // namespace socc::sensors
