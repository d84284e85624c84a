// The real VLP-32C bag (nebula's decoder test data, ../shared/data/raw_sensors/03_*) against
// nebula's reference cloud: SingleStrongest, 0.4-50 m, cloud angles 270-90 deg, VLP32.yaml.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <vector>

#include "pcd_reference.hpp"
#include "raw_sensor_data.hpp"
#include "socc/sensors/recording.hpp"

namespace socc::sensors {
namespace {

RecordingOptions nebulaSettings() {
  RecordingOptions o;
  o.sensor.model = "vlp32c";
  o.sensor.calibration = test::vlp32cDir() / "VLP32.yaml";
  o.sensor.returns = ReturnMode::kStrongest;
  o.sensor.min_range = 0.4;
  o.sensor.max_range = 50.0;
  // The sensor sends 270..90 deg only: a cut in the blind half gives nebula's one cloud per
  // message; the first sweep does not start at the cut, so it is kept as partial.
  o.sensor.cut_azimuth_deg = 180.0;
  o.sensor.keep_partial = true;
  return o;
}

std::unique_ptr<ScanStream> openVlp32cBag(const RecordingOptions& o) {
  const std::filesystem::path db3 = test::vlp32cDir() / "1713492677464078412_0.db3";
  return openRecording(db3, o);
}

// nebula's azimuth rule, as its VLP-32C decoder (tier4/nebula 6d55141e, which wrote the reference
// cloud) applies it, turned into a turn of each of our points about the vertical axis (VLP32.yaml
// has no horizontal or vertical offsets, so that is exact). nebula advances laser j's azimuth by
// j x 2.304 us of rotation (the block-to-block azimuth step times j x 2.304 / 55.296) in blocks 0
// to 10 of a packet and not at all in block 11 (its azimuth step there is 0); the decoder, like
// the manual's timing table and VeloView, by the firing time of laser j's pair, j / 2 x 2.304 us.
class NebulaAzimuthRule {
 public:
  explicit NebulaAzimuthRule(const SensorScan& sweep) : sweep_(sweep) {
    // The sweep starts with block 0 of the bag's first packet and holds no blind sector, so the
    // firing sequences lie on a 55.296 us grid from its first one, 12 to a packet.
    first_us_ = 1e30;
    for (std::size_t i = 0; i < sweep.size(); ++i) first_us_ = std::min(first_us_, sequenceUs(i));
    rad_per_us_ = rotationRate();
  }

  /// Our point i where nebula's azimuth rule puts it.
  Eigen::Vector3f moved(std::size_t i) const {
    const int j = sweep_.ring[i];
    const long block = std::lround((sequenceUs(i) - first_us_) / kSequenceUs) % 12;
    const double extra_us = kFiringUs * (block < 11 ? j - j / 2 : -(j / 2));
    // Velodyne's azimuth turns clockwise seen from above: a larger azimuth is a smaller yaw.
    const Eigen::AngleAxisf turn(static_cast<float>(-rad_per_us_ * extra_us),
                                 Eigen::Vector3f::UnitZ());
    return turn * sweep_.points[i];
  }
  double degreesPerUs() const { return rad_per_us_ * 180.0 / M_PI; }

 private:
  static constexpr double kFiringUs = 2.304, kSequenceUs = 55.296;

  // The start of point i's firing sequence [us after the sweep's stamp].
  double sequenceUs(std::size_t i) const {
    return sweep_.time[i] * 1e6 - kFiringUs * (sweep_.ring[i] / 2);
  }
  // Yaw against firing time of laser 0 (the first to fire, no timing offset): the turn rate.
  double rotationRate() const {
    double st = 0, sa = 0, stt = 0, sta = 0, n = 0, prev = 0, unwrap = 0;
    bool first = true;
    for (std::size_t i = 0; i < sweep_.size(); ++i) {
      if (sweep_.ring[i] != 0) continue;
      double a = -std::atan2(sweep_.points[i].y(), sweep_.points[i].x());
      if (!first && a + unwrap < prev - M_PI) unwrap += 2 * M_PI;
      a += unwrap;
      first = false;
      prev = a;
      const double t = sweep_.time[i] * 1e6;
      st += t, sa += a, stt += t * t, sta += t * a, n += 1;
    }
    return (n * sta - st * sa) / (n * stt - st * st);
  }

  const SensorScan& sweep_;
  double first_us_ = 0, rad_per_us_ = 0;
};

TEST(VelodyneVlp32c, MatchesNebulasReferenceCloud) {
  SOCC_REQUIRE_RAW_SENSORS();
  const std::vector<Eigen::Vector3f> reference =
      test::readBinaryXyzPcd(test::vlp32cDir() / "ground_truth_1713492677464078412.pcd");
  ASSERT_EQ(reference.size(), 26216u);
  std::unique_ptr<ScanStream> stream = openVlp32cBag(nebulaSettings());
  std::vector<SensorScan> scans;
  while (std::optional<SensorScan> s = stream->next()) scans.push_back(std::move(*s));
  // One sweep per message of the bag (the first kept as partial: it does not start at the cut),
  // and the start of a sixth turn, which the last packet holds after its blind sector.
  ASSERT_EQ(scans.size(), 6u) << stream->problems();
  for (std::size_t i = 1; i < 5; ++i) EXPECT_TRUE(scans[i].complete) << i;
  EXPECT_EQ(stream->problems().find("packets lost"), std::string::npos) << stream->problems();
  // nebula's cloud angles 270-90 deg select firings by their block azimuth: the sensor sends
  // only those, so every decoded point counts (the beams' azimuth offsets reach 4.2 deg beyond).
  const SensorScan& sweep = scans.front();
  const std::vector<Eigen::Vector3f>& ours = sweep.points;
  EXPECT_NEAR(static_cast<double>(ours.size()), static_cast<double>(reference.size()),
              0.002 * reference.size());
  // Ranges, elevations and beam offsets agree; the azimuths within a firing sequence differ by
  // nebula's rule (NebulaAzimuthRule), up to 36.9 us of rotation (0.13 deg: 5.6 cm at the cloud's
  // 24 m). With that rule applied to our points, the clouds agree within 1 cm both ways: the
  // rule is the whole difference.
  const NebulaAzimuthRule rule(sweep);
  EXPECT_NEAR(rule.degreesPerUs(), 360.0 * 10.05 * 1e-6, 0.02 * 360.0 * 10e-6);  // ~10 Hz
  std::vector<Eigen::Vector3f> as_nebula(ours.size());
  for (std::size_t i = 0; i < ours.size(); ++i) as_nebula[i] = rule.moved(i);
  const double ours_1cm = test::fractionWithin(as_nebula, reference, 0.01f);
  const double reference_1cm = test::fractionWithin(reference, as_nebula, 0.01f);
  const double raw_ours_6cm = test::fractionWithin(ours, reference, 0.06f);
  const double raw_reference_6cm = test::fractionWithin(reference, ours, 0.06f);
  std::printf(
      "with nebula's azimuth rule, within 1 cm: %.4f of ours, %.4f of nebula's; as decoded "
      "(manual's pair timing): within 1 cm %.4f and %.4f, within 6 cm %.4f and %.4f\n",
      ours_1cm, reference_1cm, test::fractionWithin(ours, reference, 0.01f),
      test::fractionWithin(reference, ours, 0.01f), raw_ours_6cm, raw_reference_6cm);
  EXPECT_GE(ours_1cm, 0.99);
  EXPECT_GE(reference_1cm, 0.99);
  EXPECT_GE(raw_ours_6cm, 0.99);
  EXPECT_GE(raw_reference_6cm, 0.99);
}

}  // namespace
}  // namespace socc::sensors
