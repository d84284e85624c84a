// Velodyne model facts from the user manuals (packet structure, firing timing, factory bytes,
// nominal elevation angles). See docs/sensors.md for the manuals they come from.
#include "velodyne_model.hpp"

#include <cmath>
#include <stdexcept>

namespace socc::sensors::velodyne {
namespace {

constexpr std::uint16_t kFlagUpper = 0xEEFF;  // bytes FF EE
constexpr std::uint16_t kFlagLower = 0xDDFF;  // bytes FF DD (HDL-64E lower block, VLS-128 bank 2)
constexpr std::uint16_t kFlagBank3 = 0xCCFF;
constexpr std::uint16_t kFlagBank4 = 0xBBFF;
constexpr std::array<std::uint16_t, 4> kBankFlags{kFlagUpper, kFlagLower, kFlagBank3, kFlagBank4};

// VLP-16 manual: 16 firings 2.304 us apart, then recharge; a sequence every 55.296 us, two
// sequences per block.
constexpr double kVlp16Firing = 2.304;
constexpr double kVlp16Sequence = 55.296;
// VLP-32C manual (9.4, table 9-5): lasers fire in pairs (0 and 1, then 2 and 3...) every
// 2.304 us; a sequence (one block) every 55.296 us. A point's azimuth follows its pair's firing
// time, as in VeloView; the pseudo code of the manual's 9.5 advances pair K/2 by K x 2.304 us,
// which puts the last pair at 69.1 us, after the next sequence (docs/sensors.md).
constexpr double kVlp32Firing = 2.304;
constexpr double kVlp32Sequence = 55.296;
// HDL-32E manual: 32 firings 1.152 us apart; a sequence (one block) every 46.08 us.
constexpr double kHdl32Firing = 1.152;
constexpr double kHdl32Sequence = 46.08;
// HDL-64E S2 / S2.1 / S3 (docs/sensors.md, "HDL-64E"): the upper (FF EE, lasers 0-31) and the
// lower block (FF DD, lasers 32-63) fire together, in groups of four lasers. Single return (S2
// and S3): a firing every 48 us, groups 6 us apart, 6 firings a packet. S3 dual return: a firing
// every 57.6 us, groups 7.2 us apart, 3 firings a packet of 4 blocks each (upper and lower
// strongest, upper and lower last). The stamp is taken at the end of the packet's last firing.
struct Hdl64Timing {
  double cycle_us;                 // one firing of all 64 lasers
  double group_us;                 // between groups of four lasers
  std::array<double, 4> in_group;  // the four lasers of a group
  int blocks_per_firing;
};
constexpr Hdl64Timing kHdl64Single{48.0, 6.0, {0.0, 1.26, 2.46, 3.66}, 2};
constexpr Hdl64Timing kHdl64Dual{57.6, 7.2, {0.0, 1.3, 2.5, 3.7}, 4};
// VLS-128 manual: groups of 8 lasers 2.665 us apart, a maintenance slot after the eighth group,
// 53.3 us per sequence; group index = laser / 8 + laser / 64; the stamp is 8.7 us after the
// sequence start.
constexpr double kVls128Group = 2.665;
constexpr double kVls128Sequence = 53.3;
constexpr double kVls128StampAfterStart = 8.7;

void setBlock(PacketLayout& l, int b, std::uint16_t flag, std::int8_t ret, float start_us) {
  l.flag[b] = flag;
  l.return_slot[b] = ret;
  l.block_start_us[b] = start_us;
  l.used[b] = true;
}

void setSlot(PacketLayout& l, int b, int c, int laser, double offset_us) {
  l.slots[b][c] = PointSlot{static_cast<std::uint16_t>(laser), static_cast<float>(offset_us),
                            static_cast<std::uint8_t>(c == 0 ? 1 : 0)};
}

std::int8_t dualSlot(bool dual, int b) {
  if (!dual) return -1;
  return static_cast<std::int8_t>(b % 2 == 0 ? 1 : 0);  // even: last, odd: strongest
}

PacketLayout vlp16(bool dual) {
  PacketLayout l;
  for (int b = 0; b < kBlocks; ++b) {
    const int first_seq = dual ? 2 * (b / 2) : 2 * b;
    setBlock(l, b, kFlagUpper, dualSlot(dual, b), static_cast<float>(kVlp16Sequence * first_seq));
    for (int c = 0; c < kChannels; ++c)
      setSlot(l, b, c, c % 16, kVlp16Sequence * (first_seq + c / 16) + kVlp16Firing * (c % 16));
  }
  l.packet_period_us = kVlp16Sequence * (dual ? 12 : 24);
  return l;
}

PacketLayout singleSequenceBlocks(bool dual, double sequence_us, double firing_us,
                                  int lasers_per_firing) {
  PacketLayout l;
  for (int b = 0; b < kBlocks; ++b) {
    const int seq = dual ? b / 2 : b;
    setBlock(l, b, kFlagUpper, dualSlot(dual, b), static_cast<float>(sequence_us * seq));
    for (int c = 0; c < kChannels; ++c)
      setSlot(l, b, c, c, sequence_us * seq + firing_us * (c / lasers_per_firing));
  }
  l.packet_period_us = sequence_us * (dual ? 6 : 12);
  return l;
}

PacketLayout hdl64(bool dual) {
  const Hdl64Timing& t = dual ? kHdl64Dual : kHdl64Single;
  const int firings = kBlocks / t.blocks_per_firing;
  PacketLayout l;
  for (int b = 0; b < kBlocks; ++b) {
    const int firing = b / t.blocks_per_firing;
    const double start = t.cycle_us * (firing - firings);
    // Dual: the first two blocks of a firing hold the strongest return, the next two the last.
    const auto ret = static_cast<std::int8_t>(dual ? (b % t.blocks_per_firing >= 2 ? 1 : 0) : -1);
    setBlock(l, b, b % 2 == 0 ? kFlagUpper : kFlagLower, ret, static_cast<float>(start));
    for (int c = 0; c < kChannels; ++c)
      setSlot(l, b, c, c + 32 * (b % 2),
              start + t.group_us * (c / 4) + t.in_group[static_cast<std::size_t>(c % 4)]);
  }
  l.packet_period_us = t.cycle_us * firings;
  return l;
}

double vls128Offset(int seq, int laser) {
  const int group = laser / 8 + laser / 64;
  return kVls128Sequence * seq + kVls128Group * group - kVls128StampAfterStart;
}

PacketLayout vls128(bool dual) {
  PacketLayout l;
  // Single: 3 sequences x 4 banks. Dual: one sequence, each bank's last and strongest blocks
  // side by side (8 blocks); the last 4 blocks carry no data.
  const int blocks = dual ? 8 : kBlocks;
  for (int b = 0; b < blocks; ++b) {
    const int bank = dual ? b / 2 : b % 4;
    const int seq = dual ? 0 : b / 4;
    setBlock(l, b, kBankFlags[static_cast<std::size_t>(bank)], dualSlot(dual, b),
             static_cast<float>(kVls128Sequence * seq - kVls128StampAfterStart));
    for (int c = 0; c < kChannels; ++c)
      setSlot(l, b, c, 32 * bank + c, vls128Offset(seq, 32 * bank + c));
  }
  l.packet_period_us = kVls128Sequence * (dual ? 1 : 3);
  return l;
}

// Dual return: each block's partner holds the other return of the same firing and bank.
void findPartners(PacketLayout& l) {
  l.partner.fill(-1);
  for (int b = 0; b < kBlocks; ++b)
    for (int o = 0; o < kBlocks && l.return_slot[b] >= 0; ++o)
      if (o != b && l.used[o] && l.flag[o] == l.flag[b] &&
          l.block_start_us[o] == l.block_start_us[b] && l.return_slot[o] == 1 - l.return_slot[b])
        l.partner[b] = static_cast<std::int8_t>(o);
}

void finishSpan(PacketLayout& l) {
  double last = -1e9;
  for (int b = 0; b < kBlocks; ++b)
    if (l.used[b])
      for (const PointSlot& s : l.slots[b]) last = std::max(last, static_cast<double>(s.offset_us));
  l.firing_span_end_us = last;
}

std::vector<ModelInfo> makeModels() {
  std::vector<ModelInfo> m;
  m.push_back({"vlp16",
               "Velodyne VLP-16 / Puck LITE",
               Family::kVlp16,
               16,
               {0x22},
               0.002,
               2 * kVlp16Sequence,
               {-15, 1, -13, 3, -11, 5, -9, 7, -7, 9, -5, 11, -3, 13, -1, 15},
               std::vector<double>(16, 0.0)});
  m.push_back(
      {"vlp32c",
       "Velodyne VLP-32C",
       Family::kVlp32c,
       32,
       {0x28},
       0.004,
       kVlp32Sequence,
       {-25,    -1,     -1.667, -15.639, -11.31, 0,      -0.667, -8.843, -7.254, 0.333,  -0.333,
        -6.148, -5.333, 1.333,  0.667,   -4,     -4.667, 1.667,  1,      -3.667, -3.333, 3.333,
        2.333,  -2.667, -3,     7,       4.667,  -2.333, -2,     15,     10.333, -1.333},
       {-1.4, 4.2, -1.4, 1.4, -1.4, 1.4, -4.2, 1.4, -1.4, 4.2, -1.4, 1.4, -4.2, 1.4, -4.2, 1.4,
        -1.4, 4.2, -1.4, 4.2, -4.2, 1.4, -1.4, 1.4, -1.4, 1.4, -1.4, 4.2, -4.2, 1.4, -1.4, 1.4}});
  m.push_back(
      {"hdl32e",
       "Velodyne HDL-32E",
       Family::kHdl32e,
       32,
       {0x21},
       0.002,
       kHdl32Sequence,
       {-30.67, -9.33,  -29.33, -8.00,  -28.00, -6.67,  -26.67, -5.33,  -25.33, -4.00,  -24.00,
        -2.67,  -22.67, -1.33,  -21.33, 0.00,   -20.00, 1.33,   -18.67, 2.67,   -17.33, 4.00,
        -16.00, 5.33,   -14.67, 6.67,   -13.33, 8.00,   -12.00, 9.33,   -10.67, 10.67},
       std::vector<double>(32, 0.0)});
  m.push_back({"hdl64e",
               "Velodyne HDL-64E S2/S3",
               Family::kHdl64e,
               64,
               {},
               0.002,
               kHdl64Single.cycle_us,
               {},
               {}});
  m.push_back({"vls128",
               "Velodyne VLS-128",
               Family::kVls128,
               128,
               {0x63, 0xA1},
               0.004,
               kVls128Sequence,
               {},
               {}});
  return m;
}

}  // namespace

const std::vector<ModelInfo>& velodyneModels() {
  static const std::vector<ModelInfo> models = makeModels();
  return models;
}

const ModelInfo* findVelodyneModel(std::string_view name) {
  for (const ModelInfo& m : velodyneModels())
    if (m.name == name) return &m;
  return nullptr;
}

PacketLayout packetLayout(const ModelInfo& model, bool dual) {
  PacketLayout l;
  switch (model.family) {
    case Family::kVlp16:
      l = vlp16(dual);
      break;
    case Family::kVlp32c:
      l = singleSequenceBlocks(dual, kVlp32Sequence, kVlp32Firing, 2);
      break;
    case Family::kHdl32e:
      l = singleSequenceBlocks(dual, kHdl32Sequence, kHdl32Firing, 1);
      break;
    case Family::kHdl64e:
      l = hdl64(dual);
      break;
    case Family::kVls128:
      l = vls128(dual);
      break;
  }
  findPartners(l);
  finishSpan(l);
  return l;
}

Calibration nominalCalibration(const ModelInfo& model) {
  if (model.vert_deg.empty())
    throw std::runtime_error(std::string(model.name) +
                             " needs its calibration file (VeloView .xml or ROS velodyne .yaml): "
                             "every unit has its own beam angles");
  Calibration cal;
  cal.distance_resolution_m = model.distance_resolution_m;
  for (std::size_t i = 0; i < model.vert_deg.size(); ++i) {
    LaserCalibration l;
    l.vert_rad = model.vert_deg[i] * M_PI / 180.0;
    l.rot_rad = model.rot_deg[i] * M_PI / 180.0;
    cal.lasers.push_back(l);
  }
  return cal;
}

}  // namespace socc::sensors::velodyne
