#include "hesai_layout.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "packet_bytes.hpp"

namespace socc::sensors {
namespace {

using packet_bytes::u16;
using packet_bytes::u32;

// Firing time of each laser within its round [ns, relative to the round's end], Laser ID 1
// first. Pandar40P manual, appendix II, table "Laser Firing Time of Each Channel".
const std::vector<std::int64_t> kPandar40pFiring = {
    -42220, -28470, -16040, -3620,  -45490, -31740, -47460, -54670, -20620, -33710,
    -40910, -8190,  -20620, -27160, -50730, -8190,  -14740, -36980, -45490, -52700,
    -23890, -31740, -38950, -11470, -18650, -25190, -48760, -6230,  -12770, -35010,
    -21920, -9500,  -43520, -29770, -17350, -4920,  -42220, -28470, -16040, -3620};

// Pandar64 manual, appendix II: t_round_end - (1.304 a + 1.968 b + 3.62) us per Laser ID.
const std::vector<std::int64_t> kPandar64Firing = {
    -23180, -21876, -20572, -19268, -17964, -16660, -11444, -46796, -7532,  -36956, -50732,
    -54668, -40892, -44828, -31052, -34988, -48764, -52700, -38924, -42860, -29084, -33020,
    -46796, -25148, -36956, -50732, -27116, -40892, -44828, -31052, -34988, -48764, -25148,
    -38924, -42860, -29084, -33020, -52700, -6228,  -54668, -15356, -27116, -10140, -23180,
    -4924,  -21876, -14052, -17964, -8836,  -19268, -3620,  -20572, -12748, -16660, -7532,
    -11444, -6228,  -15356, -10140, -4924,  -3620,  -14052, -8836,  -12748};

HesaiLayout xt32() {
  HesaiLayout l;
  l.model = "pandarxt32";
  l.lasers = 32;
  l.blocks = 8;
  l.header_size = 12;  // pre-header 6 (EE FF, protocol 6.1, reserved) + header 6
  l.unit_size = 4;
  l.size = 1076;
  l.has_sequence = true;
  // Tail: reserved 10, return mode, motor speed u16, date (year - 1900) 6, timestamp u32 [us],
  // factory information, UDP sequence u32.
  l.tail_return_mode = 10;
  l.tail_motor_speed = 11;
  l.tail_date = 13;
  l.tail_timestamp = 19;
  l.year_base = 1900;
  l.min_range = 0.05;
  l.max_range = 120.0;
  l.firing_period_us = 50.0;
  // PandarXT manual, appendix II: a round starts 50 us after the previous one, the packet's t0
  // being the last round's trigger; channel n fires 1.512 (n - 1) + 0.368 us after its round's
  // start, which is 5.632 us after the trigger.
  l.last_round_ns = 5632;
  for (int c = 0; c < l.lasers; ++c) l.channel_ns.push_back(368 + 1512 * c);
  for (int c = 0; c < l.lasers; ++c) l.nominal_elevation_deg.push_back(15.0f - c);
  return l;
}

HesaiLayout pandar40p() {
  HesaiLayout l;
  l.model = "pandar40p";
  l.lasers = 40;
  l.blocks = 10;
  l.header_size = 0;
  l.block_flag = true;
  l.unit_size = 3;
  l.size = 1262;
  // Tail: reserved 5, high temperature flag, reserved 2, motor speed u16, timestamp u32 [us],
  // return mode, factory information, date (year - 2000) 6; optional UDP sequence u32.
  l.tail_motor_speed = 8;
  l.tail_timestamp = 10;
  l.tail_return_mode = 14;
  l.tail_date = 16;
  l.year_base = 2000;
  l.min_range = 0.3;
  l.max_range = 200.0;
  l.firing_period_us = 55.56;
  // Round end times: t0 - 28.58 us for the last round, 55.56 us apart.
  l.last_round_ns = -28580;
  l.channel_ns = kPandar40pFiring;
  return l;
}

HesaiLayout pandar64() {
  HesaiLayout l = pandar40p();  // same tail and unit; a header and 6 blocks of 64 lasers
  l.model = "pandar64";
  l.lasers = 64;
  l.blocks = 6;
  l.header_size = 8;  // EE FF, laser num, block num, reserved, distance unit, reserved 2
  l.block_flag = false;
  l.size = 1194;
  l.last_round_ns = -42580;
  l.channel_ns = kPandar64Firing;
  return l;
}

// Days since 1970-01-01 of a proleptic Gregorian date (no time zone involved).
std::int64_t hesaiDaysFromCivil(int year, unsigned month, unsigned day) {
  year -= month <= 2 ? 1 : 0;
  const std::int64_t era = (year >= 0 ? year : year - 399) / 400;
  const unsigned yoe = static_cast<unsigned>(year - era * 400);
  const unsigned doy = (153 * (month + (month > 2 ? -3 : 9)) + 2) / 5 + day - 1;
  const unsigned doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  return era * 146097 + static_cast<std::int64_t>(doe) - 719468;
}

int hesaiReturnsOfMode(std::uint8_t mode) {
  switch (mode) {
    case 0x33:
    case 0x37:
    case 0x38:
      return 1;  // first, strongest, last
    case 0x39:
    case 0x3b:
    case 0x3c:
      return 2;  // last+strongest, first+last, first+strongest
    default:
      return 0;
  }
}

bool exactHesaiLayoutMatch(const HesaiLayout& l, const std::uint8_t* d, std::size_t size) {
  if (size != l.size && size != l.size + 4) return false;
  if (size < 8 || d[0] != 0xEE || d[1] != 0xFF) return false;
  if (l.model == "pandarxt32") return size == l.size + 4 && d[6] == l.lasers && d[7] == l.blocks;
  if (l.model == "pandar64") return d[2] == l.lasers && d[3] == l.blocks;
  return true;  // pandar40p: no header to check beyond the first block's flag
}

}  // namespace

std::int64_t HesaiLayout::pointOffsetNs(int block, int channel, int returns) const {
  const int rounds_before_last = (blocks - 1 - block) / returns;
  return last_round_ns -
         static_cast<std::int64_t>(std::llround(firing_period_us * 1000.0)) * rounds_before_last +
         channel_ns[static_cast<std::size_t>(channel)];
}

const std::vector<HesaiLayout>& hesaiLayouts() {
  static const std::vector<HesaiLayout> layouts = {xt32(), pandar40p(), pandar64()};
  return layouts;
}

const HesaiLayout* hesaiLayout(const std::string& model) {
  for (const HesaiLayout& l : hesaiLayouts())
    if (l.model == model) return &l;
  return nullptr;
}

std::string detectHesaiModel(const std::uint8_t* data, std::size_t size) {
  for (const HesaiLayout& l : hesaiLayouts())
    if (exactHesaiLayoutMatch(l, data, size)) return l.model;
  return {};
}

std::uint16_t hesaiBlockAzimuth(const HesaiLayout& layout, const std::uint8_t* data, int block) {
  const std::uint8_t* b = data + layout.header_size + block * layout.blockSize();
  return u16(b + (layout.block_flag ? 2 : 0));
}

const std::uint8_t* hesaiUnit(const HesaiLayout& layout, const std::uint8_t* data, int block,
                              int channel) {
  const std::uint8_t* b = data + layout.header_size + block * layout.blockSize();
  return b + (layout.block_flag ? 4 : 2) + channel * layout.unit_size;
}

HesaiCheck parseHesaiPacket(const HesaiLayout& l, const std::uint8_t* d, std::size_t size,
                            HesaiPacket& p, std::string& why) {
  const bool hesai_start = size >= 2 && d[0] == 0xEE && d[1] == 0xFF;
  if (size != l.size && size != l.size + 4) {
    const std::string other = detectHesaiModel(d, size);
    why = !other.empty() ? "a " + other + " packet (" + std::to_string(size) + " B)"
                         : std::to_string(size) + " B, not the " + std::to_string(l.size) +
                               (l.has_sequence ? "+4" : "") + " B of a " + l.model + " packet";
    return hesai_start && size < l.size && other.empty() ? HesaiCheck::kMalformed
                                                         : HesaiCheck::kForeign;
  }
  if (!hesai_start || (l.has_sequence && size != l.size + 4)) {
    why = "no Hesai start of packet";
    return HesaiCheck::kForeign;
  }
  int header_returns = 0;
  p.distance_unit_m = 0.004;
  if (l.model == "pandarxt32") {
    if (d[6] != l.lasers || d[7] != l.blocks) {
      why = "header says " + std::to_string(d[6]) + " lasers, " + std::to_string(d[7]) + " blocks";
      return HesaiCheck::kForeign;
    }
    p.distance_unit_m = d[9] * 1e-3;
    header_returns = d[10];
  } else if (l.model == "pandar64") {
    if (d[2] != l.lasers || d[3] != l.blocks) {
      why = "header says " + std::to_string(d[2]) + " lasers, " + std::to_string(d[3]) + " blocks";
      return HesaiCheck::kForeign;
    }
    p.distance_unit_m = d[5] * 1e-3;
  }
  if (p.distance_unit_m <= 0.0 || p.distance_unit_m > 0.01) {
    why = "distance unit " + std::to_string(p.distance_unit_m * 1e3) + " mm";
    return HesaiCheck::kMalformed;
  }
  if (l.block_flag) {
    for (int b = 0; b < l.blocks; ++b) {
      const std::uint8_t* block = d + l.header_size + b * l.blockSize();
      if (block[0] != 0xEE || block[1] != 0xFF) {
        why = "block " + std::to_string(b + 1) + " has no EE FF flag";
        return HesaiCheck::kMalformed;
      }
    }
  }
  const std::uint8_t* tail = d + l.tailOffset();
  p.return_mode = tail[l.tail_return_mode];
  p.returns = hesaiReturnsOfMode(p.return_mode);
  if (p.returns == 0 || (header_returns != 0 && header_returns != p.returns)) {
    char mode[8];
    std::snprintf(mode, sizeof mode, "0x%02x", p.return_mode);
    why = "return mode " + std::string(mode) + " with " + std::to_string(header_returns) +
          " returns in the header";
    return HesaiCheck::kMalformed;
  }
  for (int b = 0; b < l.blocks; ++b) {
    const std::uint16_t az = hesaiBlockAzimuth(l, d, b);
    if (az >= 36000 || (b % p.returns != 0 && az != hesaiBlockAzimuth(l, d, b - 1))) {
      why = "block " + std::to_string(b + 1) + " azimuth " + std::to_string(az);
      return HesaiCheck::kMalformed;
    }
  }
  // Laser timing cross-check: consecutive rounds are firing_period_us apart, so their azimuth
  // step follows from the motor speed (never trust one field alone).
  p.motor_rpm = u16(tail + l.tail_motor_speed);
  if (p.motor_rpm >= 150 && p.motor_rpm <= 1500 && l.blocks / p.returns >= 2) {
    const double expected = p.motor_rpm / 60.0 * 36000.0 * l.firing_period_us * 1e-6;
    const int step =
        (hesaiBlockAzimuth(l, d, p.returns) - hesaiBlockAzimuth(l, d, 0) + 36000) % 36000;
    if (std::abs(step - expected) > std::max(3.0, 0.3 * expected)) {
      why = "azimuth step " + std::to_string(step / 100.0) + " deg between firing rounds, " +
            std::to_string(expected / 100.0) + " expected at " + std::to_string(p.motor_rpm) +
            " rpm";
      return HesaiCheck::kForeign;
    }
  }
  const std::uint8_t* date = tail + l.tail_date;
  const unsigned month = date[1], day = date[2];
  const std::uint32_t us = u32(tail + l.tail_timestamp);
  if (month < 1 || month > 12 || day < 1 || day > 31 || date[3] > 23 || date[4] > 59 ||
      date[5] > 60 || us >= 1000000) {
    why = "bad date or time in the tail";
    return HesaiCheck::kMalformed;
  }
  const std::int64_t seconds = hesaiDaysFromCivil(l.year_base + date[0], month, day) * 86400 +
                               date[3] * 3600 + date[4] * 60 + date[5];
  p.time_ns = seconds * 1000000000 + static_cast<std::int64_t>(us) * 1000;
  p.has_sequence = size == l.size + 4;
  p.sequence = p.has_sequence ? u32(d + l.size) : 0;
  return HesaiCheck::kOk;
}

}  // namespace socc::sensors
