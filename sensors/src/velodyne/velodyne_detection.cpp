#include "velodyne_detection.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "velodyne_packet.hpp"

namespace socc::sensors::velodyne {
namespace {

enum class Banks { kOne, kUpperLower, kFour, kUnknown };

struct Evidence {
  Banks banks = Banks::kUnknown;
  bool dual = false;
  double period_us = 0.0;   // median sensor-stamp step between packets; 0: unknown
  double deg_per_us = 0.0;  // rotation speed from the azimuth advance between packets
  std::vector<std::uint16_t> first_azimuth;  // per packet (hundredths)
  std::vector<const Packet*> packets;
  int product_id = -1;
  int return_mode = -1;
};

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

Banks banksOf(const std::vector<std::uint8_t>& d) {
  bool all_upper = true;
  bool upper_lower = true;
  bool four = true;
  constexpr std::uint16_t kUpper = 0xEEFF, kLower = 0xDDFF, kThird = 0xCCFF, kFourth = 0xBBFF;
  const std::uint16_t single4[4] = {kUpper, kLower, kThird, kFourth};
  bool four_dual = true;
  for (int b = 0; b < kBlocks; ++b) {
    const std::uint16_t f = blockFlag(d, b);
    all_upper = all_upper && f == kUpper;
    upper_lower = upper_lower && f == (b % 2 == 0 ? kUpper : kLower);
    four = four && f == single4[b % 4];
    four_dual = four_dual && (b >= 8 || f == single4[b / 2]);
  }
  if (all_upper) return Banks::kOne;
  if (upper_lower) return Banks::kUpperLower;
  if (four || four_dual) return Banks::kFour;
  return Banks::kUnknown;
}

// Dual return: the blocks of one firing's two returns carry the same azimuth; the HDL-64E S3
// sends upper and lower block of the strongest, then of the last return (4 blocks a firing;
// single return: an upper/lower pair a firing, the next pair 48 us, >= 8 hundredths, later).
bool pairsShareAzimuth(const std::vector<std::uint8_t>& d, Banks banks) {
  if (banks == Banks::kFour) return blockFlag(d, 0) == blockFlag(d, 1);
  const int stride = banks == Banks::kUpperLower ? 4 : 2;
  if (banks != Banks::kOne && banks != Banks::kUpperLower) return false;
  for (int b = 0; b < kBlocks; ++b)
    if (b % stride < stride / 2 && blockAzimuth(d, b) != blockAzimuth(d, b + stride / 2))
      return false;
  return true;
}

template <typename T>
T mostCommon(const std::vector<T>& v, T fallback) {
  T best = fallback;
  std::size_t best_count = 0;
  for (const T& x : v) {
    const auto n = static_cast<std::size_t>(std::count(v.begin(), v.end(), x));
    if (n > best_count) {
      best = x;
      best_count = n;
    }
  }
  return best;
}

Evidence gather(const std::vector<Packet>& packets) {
  Evidence e;
  std::vector<Banks> banks;
  std::vector<int> products, modes;
  std::size_t dual_votes = 0;
  for (const Packet& p : packets) {
    const Banks b = banksOf(p.data);
    banks.push_back(b);
    if (pairsShareAzimuth(p.data, b)) ++dual_votes;
    products.push_back(p.data[kProductIdOffset]);
    modes.push_back(p.data[kReturnModeOffset]);
    e.first_azimuth.push_back(blockAzimuth(p.data, 0));
    e.packets.push_back(&p);
  }
  e.banks = mostCommon(banks, Banks::kUnknown);
  e.dual = dual_votes * 10 >= packets.size() * 9;
  e.product_id = mostCommon(products, -1);
  e.return_mode = mostCommon(modes, -1);
  std::vector<double> steps, rates;
  for (std::size_t i = 1; i < packets.size(); ++i) {
    const double dt = static_cast<double>(packetStamp(packets[i].data)) -
                      static_cast<double>(packetStamp(packets[i - 1].data));
    if (!(dt > 0.0) || dt > 1e5) continue;
    steps.push_back(dt);
    rates.push_back(azimuthStep(e.first_azimuth[i - 1], e.first_azimuth[i]) / 100.0 / dt);
  }
  e.period_us = median(steps);
  e.deg_per_us = median(rates);
  return e;
}

Banks banksFor(Family f) {
  switch (f) {
    case Family::kHdl64e:
      return Banks::kUpperLower;
    case Family::kVls128:
      return Banks::kFour;
    default:
      return Banks::kOne;
  }
}

const char* banksText(Banks b) {
  switch (b) {
    case Banks::kOne:
      return "every block flagged FF EE (VLP-16, VLP-32C, HDL-32E)";
    case Banks::kUpperLower:
      return "upper/lower blocks FF EE / FF DD (HDL-64E)";
    case Banks::kFour:
      return "four banks FF EE..FF BB (VLS-128)";
    default:
      return "block flags of no known Velodyne model";
  }
}

std::string fmt(const char* f, double a, double b = 0.0, double c = 0.0) {
  char buf[160];
  std::snprintf(buf, sizeof buf, f, a, b, c);
  return buf;
}

// The azimuth advance within a packet from its first to its last firing sequence, which the
// model's block timing predicts from the rotation speed seen between packets.
std::string checkAzimuthSteps(const ModelInfo& m, const Evidence& e) {
  if (e.deg_per_us <= 0.0) return {};
  const PacketLayout layout = packetLayout(m, e.dual);
  int last = 0;
  for (int b = 0; b < kBlocks; ++b)
    if (layout.used[b]) last = b;
  const double span_us = layout.block_start_us[last] - layout.block_start_us[0];
  if (span_us <= 0.0) return {};
  std::vector<double> advance;
  for (const Packet* p : e.packets)
    advance.push_back(azimuthStep(blockAzimuth(p->data, 0), blockAzimuth(p->data, last)) / 100.0);
  const double measured = median(advance);
  const double expected = e.deg_per_us * span_us;
  if (std::abs(measured - expected) <= 0.2 * expected + 0.02) return {};
  return fmt(
      "the azimuth advances %.2f deg from the first to the last firing of a packet, where "
      "this model's firing timing at the measured %.1f Hz predicts %.2f deg",
      measured, e.deg_per_us * 1e6 / 360.0, expected);
}

std::string checkModel(const ModelInfo& m, const Evidence& e) {
  if (banksFor(m.family) != e.banks) return std::string("the packets have ") + banksText(e.banks);
  const double expected = packetLayout(m, e.dual).packet_period_us;
  if (e.period_us > 0.0) {
    // HDL-64E: 25 %, the firing cycles the references give differ by up to 20 % (docs).
    const double tolerance = m.family == Family::kHdl64e ? 0.25 : 0.05;
    const bool ok = std::abs(e.period_us / expected - 1.0) < tolerance;
    if (!ok)
      return fmt("a packet comes every %.1f us (sensor stamps), where this model sends one every "
                 "%.1f us",
                 e.period_us, expected) +
             (e.dual ? " in dual return mode" : " in single return mode");
    const double hz = e.deg_per_us * 1e6 / 360.0;
    if (hz < 2.0 || hz > 25.0) return fmt("the packets imply %.1f rotations a second", hz);
  }
  return checkAzimuthSteps(m, e);
}

const ModelInfo* modelOfProductId(int id) {
  for (const ModelInfo& m : velodyneModels())
    if (std::find(m.product_ids.begin(), m.product_ids.end(), id) != m.product_ids.end()) return &m;
  return nullptr;
}

std::string factoryText(int id) {
  const ModelInfo* m = modelOfProductId(id);
  char buf[96];
  std::snprintf(buf, sizeof buf, "factory byte 0x%02X (%s)", id & 0xFF,
                m ? std::string(m->name).c_str() : "no known model");
  return buf;
}

std::string measuredText(const Evidence& e) {
  return std::string(banksText(e.banks)) + (e.dual ? ", dual return pairs" : "") +
         fmt(", a packet every %.1f us, %.1f rotations a second", e.period_us,
             e.deg_per_us * 1e6 / 360.0) +
         ", " + factoryText(e.product_id);
}

}  // namespace

Detection detectModel(const std::vector<Packet>& packets, const ModelInfo* configured) {
  if (packets.empty())
    throw std::runtime_error("no Velodyne data packets to detect the model from");
  const Evidence e = gather(packets);
  std::vector<const ModelInfo*> fitting;
  for (const ModelInfo& m : velodyneModels())
    if (checkModel(m, e).empty()) fitting.push_back(&m);
  const ModelInfo* by_byte = modelOfProductId(e.product_id);
  Detection d;
  d.dual = e.dual;
  if (configured != nullptr) {
    if (const std::string why = checkModel(*configured, e); !why.empty()) {
      std::string msg =
          "the packets do not come from a " + std::string(configured->name) + ": " + why;
      if (fitting.size() == 1) msg += "; they look like a " + std::string(fitting.front()->name);
      throw std::runtime_error(msg + " (" + measuredText(e) + ")");
    }
    d.model = configured;
  } else {
    if (fitting.empty())
      throw std::runtime_error("the packets fit no Velodyne model (" + measuredText(e) +
                               "); name it with --sensor");
    d.model = fitting.front();
    if (fitting.size() > 1) {
      if (by_byte == nullptr || std::find(fitting.begin(), fitting.end(), by_byte) == fitting.end())
        throw std::runtime_error("the packets fit several Velodyne models (" + measuredText(e) +
                                 "); name it with --sensor");
      d.model = by_byte;
    }
  }
  if (by_byte != nullptr && by_byte != d.model && d.model->family != Family::kHdl64e)
    d.note = factoryText(e.product_id) + " disagrees with the packet timing and azimuth steps (" +
             fmt("a packet every %.1f us", e.period_us) + "): decoded as " +
             std::string(d.model->name);
  return d;
}

}  // namespace socc::sensors::velodyne
