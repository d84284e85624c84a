// Every Velodyne model decoded from synthetic packets whose expected point positions and times
// are worked out here from the user manuals (packet layout, firing timing tables), independently
// of the decoder's tables: distances and reflectivities encode which block, channel and packet a
// point came from, so each decoded point is checked against its own expectation.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <memory>
#include <vector>

#include "../temp_dir.hpp"
#include "socc/sensors/sensor_config.hpp"
#include "velodyne_model_cases.hpp"

namespace socc::sensors {
namespace {

struct Decoded {
  std::vector<SensorScan> scans;
  DecodeStats stats;
};

Decoded decode(const test::ModelCase& m, const std::vector<Packet>& packets, SensorConfig config) {
  config.model = m.model;
  config.keep_partial = true;
  if (m.needs_calibration) {
    config.calibration = socc::testing::processTempDir() /
                         (m.model + (m.mode == 0x39 ? "_dual" : "") + "_calibration.yaml");
    test::writeYamlCalibration(config.calibration, m.vert_deg, m.resolution);
  }
  std::unique_ptr<ScanDecoder> decoder = makeDecoder(config);
  Decoded d;
  for (const Packet& p : packets) decoder->feed(p, d.scans);
  decoder->flush(d.scans);
  d.stats = decoder->stats();
  return d;
}

// Every point where the manual puts it: its laser's elevation, its distance, its azimuth at its
// firing time, and its time relative to the sweep's first point.
void checkPoints(const test::ModelCase& m, const std::vector<Packet>& packets, const Decoded& d) {
  std::size_t checked = 0;
  for (const SensorScan& s : d.scans) {
    double t0 = 0.0;
    for (std::size_t i = 0; i < s.size(); ++i) {
      const Eigen::Vector3f& p = s.points[i];
      const double range = p.norm();
      const int raw = static_cast<int>(std::lround(range / m.resolution)) - 1500;
      const int b = raw / 32, c = raw % 32;
      const int k = static_cast<int>(s.intensity[i]);
      ASSERT_TRUE(b >= 0 && b < m.blocks && k < static_cast<int>(packets.size()))
          << m.model << " point " << i;
      const int laser = m.laser(b, c);
      ASSERT_EQ(s.ring[i], laser) << m.model << " block " << b << " channel " << c;
      const double elevation = std::asin(p.z() / range) * 180.0 / M_PI;
      ASSERT_NEAR(elevation, m.vert_deg[static_cast<std::size_t>(laser)], 1e-3)
          << m.model << " laser " << laser;
      const double stamp = std::round(
          static_cast<double>(packets[static_cast<std::size_t>(k)].stamp_ns - 2'000'000) / 1000.0);
      const double fired = stamp + m.offset(b, c);
      if (i == 0) t0 = fired - s.time[0] * 1e6;
      ASSERT_NEAR(s.time[i] * 1e6, fired - t0, 0.02)
          << m.model << " block " << b << " channel " << c;
      const double block_az =
          std::lround(std::fmod(test::kHundredthsPerUs * (stamp + m.block_start(b)), 36000.0)) /
          100.0;
      const double rot = m.rot_deg.empty() ? 0.0 : m.rot_deg[static_cast<std::size_t>(laser)];
      const double expected_az =
          block_az + test::kHundredthsPerUs / 100.0 * (m.offset(b, c) - m.block_start(b)) - rot;
      const double az = std::atan2(-p.y(), p.x()) * 180.0 / M_PI;
      // The decoder measures the rotation from the block azimuths (whole hundredths).
      ASSERT_NEAR(std::remainder(az - expected_az, 360.0), 0.0, 0.02)
          << m.model << " block " << b << " channel " << c;
      ++checked;
    }
  }
  EXPECT_GT(checked, 0u);
}

class VelodyneModels : public ::testing::TestWithParam<test::ModelCase> {};

TEST_P(VelodyneModels, PointsWhereTheManualPutsThem) {
  const test::ModelCase& m = GetParam();
  const std::vector<Packet> packets = test::makePackets(m, 200, 1'000'000'000u);
  const Decoded d = decode(m, packets, SensorConfig{});
  EXPECT_EQ(d.stats.packets, packets.size());
  EXPECT_EQ(d.stats.gaps, 0u);
  EXPECT_EQ(d.stats.malformed + d.stats.foreign + d.stats.late, 0u);
  std::size_t points = 0;
  for (const SensorScan& s : d.scans) points += s.size();
  // Every data point (dual: the last and the strongest return differ here, both are kept).
  EXPECT_EQ(points, packets.size() * static_cast<std::size_t>(m.blocks) * 32u);
  checkPoints(m, packets, d);
}

INSTANTIATE_TEST_SUITE_P(Manuals, VelodyneModels,
                         ::testing::Values(test::hdl32e(), test::vlp32c(), test::vlp16(false),
                                           test::vlp16(true), test::hdl64e(false),
                                           test::hdl64e(true), test::vls128(false),
                                           test::vls128(true)),
                         [](const ::testing::TestParamInfo<test::ModelCase>& param_info) {
                           const test::ModelCase& m = param_info.param;
                           return m.model + (m.mode == 0x39 ? "_dual" : "");
                         });

}  // namespace
}  // namespace socc::sensors
