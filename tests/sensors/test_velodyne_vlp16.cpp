// The real VLP-16 capture (VeloView's test data, ../shared/data/raw_sensors/01_*) decoded as
// VeloView's own vlp-16.test expects, with the firing times of the VLP-16 manual.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "raw_sensor_data.hpp"
#include "socc/sensors/pcap_source.hpp"
#include "socc/sensors/recording.hpp"

namespace socc::sensors {
namespace {

std::vector<SensorScan> readVlp16(const RecordingOptions& options,
                                  std::string* problems = nullptr) {
  std::unique_ptr<ScanStream> stream = openRecording(test::vlp16Pcap(), options);
  std::vector<SensorScan> scans;
  while (std::optional<SensorScan> s = stream->next()) scans.push_back(std::move(*s));
  if (problems != nullptr) *problems = stream->problems();
  return scans;
}

RecordingOptions vlp16Options(bool keep_partial) {
  RecordingOptions o;
  o.sensor.model = "vlp16";
  o.sensor.calibration = test::vlp16Xml();
  o.sensor.keep_partial = keep_partial;
  return o;
}

// VeloView's frame: x right, y forward; socc's: x forward, y left.
Eigen::Vector3f fromVeloView(float x, float y, float z) {
  return {y, -x, z};
}
double azimuthDeg(const Eigen::Vector3f& p) {
  return std::atan2(-p.y(), p.x()) * 180.0 / M_PI;
}

// vlp-16.test: 52 frames (the first and last partial: VeloView keeps them), frames 0, 2, 16 and
// 51 with 5736, 13898, 13860 and 274 points (VeloView counts the echoes with a non-zero
// distance), and frame 16's first and last points.
TEST(VelodyneVlp16, FramesAndPointsAsVeloView) {
  SOCC_REQUIRE_RAW_SENSORS();
  std::string problems;
  const std::vector<SensorScan> scans = readVlp16(vlp16Options(true), &problems);
  ASSERT_EQ(scans.size(), 52u);
  EXPECT_FALSE(scans.front().complete);
  EXPECT_FALSE(scans.back().complete);
  for (std::size_t i = 1; i + 1 < scans.size(); ++i) EXPECT_TRUE(scans[i].complete) << i;
  EXPECT_EQ(scans[0].size(), 5736u);
  EXPECT_EQ(scans[2].size(), 13898u);
  EXPECT_EQ(scans[16].size(), 13860u);
  EXPECT_EQ(scans[51].size(), 274u);
  // The factory byte says HDL-32E; the decoder says why it decoded a VLP-16 anyway.
  EXPECT_NE(problems.find("factory byte 0x21 (hdl32e) disagrees"), std::string::npos) << problems;

  const SensorScan& f16 = scans[16];
  // Point 0: laser 0, first firing of its block: exactly VeloView's.
  const Eigen::Vector3f first = fromVeloView(0.0801272f, 6.04037f, -1.61865f);
  EXPECT_LT((f16.points[0] - first).norm(), 1e-4f);
  EXPECT_EQ(f16.intensity[0], 4.0f);
  EXPECT_EQ(f16.ring[0], 0);
  // Point 13859: laser 15 at the end of a block's second firing sequence. Same distance and
  // elevation; its azimuth is 0.25 deg further on here: the VLP-16 manual interpolates the
  // azimuth to each laser's firing time (15 x 2.304 us later than the sequence's start at
  // 20 turns a second), VeloView's code of the time took the sequence's azimuth for all 16.
  const Eigen::Vector3f last = fromVeloView(-0.0308793f, 4.91453f, 1.31687f);
  const Eigen::Vector3f& ours = f16.points.back();
  EXPECT_NEAR(ours.norm(), last.norm(), 1e-4);
  EXPECT_NEAR(ours.z(), last.z(), 1e-4);
  const double rotation = std::remainder(azimuthDeg(ours) - azimuthDeg(last), 360.0);
  const double firing_time_rotation = 360.0 * 20.0 * 15 * 2.304e-6;  // ~0.25 deg
  EXPECT_NEAR(rotation, firing_time_rotation, 0.01);
  EXPECT_EQ(f16.intensity.back(), 29.0f);
  EXPECT_EQ(f16.ring.back(), 15);
}

TEST(VelodyneVlp16, PartialSweepsDroppedByDefault) {
  SOCC_REQUIRE_RAW_SENSORS();
  const std::vector<SensorScan> scans = readVlp16(vlp16Options(false));
  ASSERT_EQ(scans.size(), 50u);
  for (const SensorScan& s : scans) EXPECT_TRUE(s.complete);
  EXPECT_EQ(scans[15].size(), 13860u);  // VeloView's frame 16
  EXPECT_EQ(scans.front().seq, 0);
  EXPECT_EQ(scans.back().seq, 49);
}

// Per-point times follow the manual's firing table (2.304 us between the lasers of a sequence,
// 55.296 us between sequences), never decrease within a sweep, and sit on the capture's clock.
TEST(VelodyneVlp16, PointTimesFollowTheFiringTable) {
  SOCC_REQUIRE_RAW_SENSORS();
  const std::vector<SensorScan> scans = readVlp16(vlp16Options(true));
  ASSERT_EQ(scans.size(), 52u);
  for (const SensorScan& s : scans) {
    ASSERT_EQ(s.time.size(), s.size());
    EXPECT_EQ(*std::min_element(s.time.begin(), s.time.end()), 0.0f);
    for (std::size_t i = 1; i < s.size(); ++i) {
      ASSERT_GE(s.time[i], s.time[i - 1]) << "scan " << s.seq << " point " << i;
      const double dt_us = (s.time[i] - s.time[i - 1]) * 1e6;
      if (s.ring[i] > s.ring[i - 1] && dt_us < 40.0) {  // two lasers of one firing sequence
        ASSERT_NEAR(dt_us, 2.304 * (s.ring[i] - s.ring[i - 1]), 0.01)
            << "scan " << s.seq << " point " << i;
      }
    }
  }
  // A whole turn at about 20 Hz, and consecutive sweeps follow each other without overlap.
  for (std::size_t i = 1; i + 1 < scans.size(); ++i) {
    const double duration = scans[i].time.back();
    EXPECT_NEAR(duration, 0.05, 0.003) << i;
    const double to_next = static_cast<double>(scans[i + 1].stamp_ns - scans[i].stamp_ns) * 1e-9;
    // The next sequence starts ~55 us later (a lost packet: 1.3 ms), give or take the arrival
    // delay's jitter, by which the clock offset is refined between sweeps.
    EXPECT_GT(to_next, duration - 100e-6) << i;
    EXPECT_LT(to_next, duration + 1.5e-3) << i;
  }
  // The stamps are on the capture's clock: a sweep's last firing precedes the capture of the
  // capture's last data packet, and the first sweep starts within a packet of the first capture.
  std::unique_ptr<PacketSource> pcap = openPcap(test::vlp16Pcap(), 2368);
  std::int64_t first_capture = 0, last_capture = 0;
  while (std::optional<Packet> p = pcap->next()) {
    if (first_capture == 0) first_capture = p->stamp_ns;
    last_capture = p->stamp_ns;
  }
  const auto end_of = [](const SensorScan& s) {
    return s.stamp_ns + static_cast<std::int64_t>(s.time.back() * 1e9);
  };
  EXPECT_LE(end_of(scans.back()), last_capture);
  EXPECT_LE(scans.front().stamp_ns, first_capture);
  EXPECT_GT(scans.front().stamp_ns, first_capture - 3'000'000);
}

}  // namespace
}  // namespace socc::sensors
