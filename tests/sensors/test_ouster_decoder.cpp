// Ouster decoding of the OS-1-128 low-bandwidth capture (raw_sensors/05) checked against the
// Ouster SDK's poses, and synthetic packets of every profile built from Ouster's packet docs.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "cloud_match.hpp"
#include "socc/sensors/ouster_decoder.hpp"
#include "socc/sensors/pcap_source.hpp"

namespace socc::sensors {
namespace {

namespace fs = std::filesystem;

fs::path osFolder() {
  return fs::path(SOCC_SHARED_DATA_DIR) / "raw_sensors" / "05_ouster_os1-128_lb_3frames";
}

std::vector<SensorScan> decodeOusterPackets(ScanDecoder& decoder,
                                            const std::vector<Packet>& packets) {
  std::vector<SensorScan> scans;
  for (const Packet& p : packets) decoder.feed(p, scans);
  decoder.flush(scans);
  return scans;
}

// The SDK's poses (KITTI 3x4 rows).
std::vector<Eigen::Isometry3d> readKittiPoses(const fs::path& file) {
  std::ifstream in(file);
  std::vector<Eigen::Isometry3d> poses;
  Eigen::Matrix<double, 3, 4, Eigen::RowMajor> m;
  while (in >> m(0, 0)) {
    for (int i = 1; i < 12; ++i) in >> m.data()[i];
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.matrix().topRows<3>() = m;
    poses.push_back(pose);
  }
  return poses;
}

// A frame's points moved to where the sensor was at mid-sweep, for a constant velocity [m/s]
// in the sensor frame (rotation neglected: the capture drives straight): uses the per-point times.
std::vector<Eigen::Vector3f> deskewed(const SensorScan& scan, const Eigen::Vector3d& velocity) {
  std::vector<Eigen::Vector3f> out;
  const double mid = scan.time.back() / 2;
  for (std::size_t i = 0; i < scan.size(); ++i)
    out.push_back(scan.points[i] + (velocity * (scan.time[i] - mid)).cast<float>());
  return out;
}

// Unit normal of cloud[i] (smallest principal axis of its 12 nearest points); zero where the
// neighbourhood is not planar. Computed on demand: registration needs few of them.
class LazyNormals {
 public:
  LazyNormals(const std::vector<Eigen::Vector3f>& cloud, const test_io::NearestPoints& tree)
      : cloud_(cloud), tree_(tree), normal_(cloud.size()), known_(cloud.size(), false) {}
  const Eigen::Vector3d& operator()(std::size_t i) {
    if (known_[i]) return normal_[i];
    known_[i] = true;
    normal_[i].setZero();
    const auto near = tree_.knn(cloud_[i], 12);
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const unsigned j : near) mean += cloud_[j].cast<double>();
    mean /= static_cast<double>(near.size());
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (const unsigned j : near) {
      const Eigen::Vector3d d = cloud_[j].cast<double>() - mean;
      cov += d * d.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
    if (eig.eigenvalues()(0) < 0.05 * eig.eigenvalues()(1)) normal_[i] = eig.eigenvectors().col(0);
    return normal_[i];
  }

 private:
  const std::vector<Eigen::Vector3f>& cloud_;
  const test_io::NearestPoints& tree_;
  std::vector<Eigen::Vector3d> normal_;
  std::vector<bool> known_;
};

struct CloudRegistration {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // target_T_source
  double inlier_fraction = 0.0;  // sampled source points within 5 cm of a target surface
};

// Point-to-plane ICP (Gauss-Newton, small angles) of source onto target from identity.
CloudRegistration registerClouds(const std::vector<Eigen::Vector3f>& source,
                                 const std::vector<Eigen::Vector3f>& target) {
  const test_io::NearestPoints tree(target);
  LazyNormals target_normals(target, tree);
  std::vector<Eigen::Vector3d> sample;
  for (std::size_t i = 0; i < source.size(); i += 13) sample.push_back(source[i].cast<double>());
  CloudRegistration r;
  for (int iteration = 0; iteration < 25; ++iteration) {
    const double max_distance = iteration < 8 ? 1.0 : 0.3;
    Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Zero();
    std::size_t inliers = 0;
    for (const auto& p : sample) {
      const Eigen::Vector3d q = r.pose * p;
      const auto [d2, j] = tree.nearest(q.cast<float>());
      const Eigen::Vector3d& n = target_normals(j);
      if (d2 > max_distance * max_distance || n.isZero()) continue;
      const double e = n.dot(q - target[j].cast<double>());
      inliers += std::abs(e) < 0.05 ? 1 : 0;
      Eigen::Matrix<double, 6, 1> J;
      J << n, q.cross(n);
      H += J * J.transpose();
      g += J * e;
    }
    r.inlier_fraction = static_cast<double>(inliers) / static_cast<double>(sample.size());
    const Eigen::Matrix<double, 6, 1> dx = H.ldlt().solve(-g);
    Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
    step.translate(dx.head<3>());
    if (dx.tail<3>().norm() > 0)
      step.rotate(Eigen::AngleAxisd(dx.tail<3>().norm(), dx.tail<3>().normalized()));
    r.pose = step * r.pose;
  }
  return r;
}

/// The UDP payloads to `port` of a capture, through the library's pcap source.
std::vector<Packet> udpPayloads(const fs::path& pcap, std::uint16_t port) {
  const std::unique_ptr<PacketSource> source = openPcap(pcap, port);
  std::vector<Packet> packets;
  while (std::optional<Packet> p = source->next()) packets.push_back(std::move(*p));
  EXPECT_EQ(source->problems(), "") << pcap;
  return packets;
}

TEST(OusterOs1_128, LowBandwidthCaptureDecodesThreeCompleteFrames) {
  if (!fs::exists(fs::path(SOCC_SHARED_DATA_DIR))) GTEST_SKIP() << "no shared data";
  const fs::path pcap = osFolder() / "OS-1-128_v2.3.0_1024x10_lb_n3.pcap";
  std::vector<Packet> packets = udpPayloads(pcap, 7502);
  ASSERT_EQ(packets.size(), 192u);
  EXPECT_EQ(packets.front().data.size(), 8448u);
  // The IMU packets (port 7503) mixed in, by capture time: skipped, never decoded.
  std::vector<Packet> imu = udpPayloads(pcap, 7503);
  EXPECT_EQ(imu.size(), 30u);
  packets.insert(packets.end(), imu.begin(), imu.end());
  std::stable_sort(packets.begin(), packets.end(),
                   [](const Packet& a, const Packet& b) { return a.stamp_ns < b.stamp_ns; });

  SensorConfig config;
  config.model = "os1-128";
  config.calibration = osFolder() / "OS-1-128_v2.3.0_1024x10.json";
  auto decoder = makeOusterDecoder(config);
  EXPECT_EQ(decoder->model(), "os1-128");
  const std::vector<SensorScan> frames = decodeOusterPackets(*decoder, packets);
  const DecodeStats& stats = decoder->stats();
  EXPECT_EQ(stats.packets, 192u);
  EXPECT_EQ(stats.foreign, 30u);
  EXPECT_EQ(stats.malformed + stats.late + stats.gaps + stats.partial_scans, 0u);
  ASSERT_EQ(frames.size(), 3u);
  const int first_frame_id = packets.front().data[2] + 256 * packets.front().data[3];

  for (const SensorScan& f : frames) {
    std::cout << "frame " << f.seq << ": " << f.size() << " points, stamp " << f.stamp_ns
              << " ns, times 0.." << f.time.back() << " s\n";
    EXPECT_TRUE(f.complete);
    EXPECT_GT(f.size(), 60000u);  // of 128 x 1024 pixels; the rest had no return
    ASSERT_EQ(f.time.size(), f.size());
    ASSERT_EQ(f.ring.size(), f.size());
    for (std::size_t i = 0; i < f.size(); ++i) {
      ASSERT_TRUE(f.points[i].allFinite());
      ASSERT_GE(f.points[i].norm(), 0.2f);  // no zero-range garbage at the sensor's origin
      ASSERT_LT(f.ring[i], 128);
    }
    // Points come column by column: times never decrease, and the distinct times are the
    // column timestamps of the frame's packets (read here straight from the bytes: u64 at the
    // start of each 524 B column after the 32 B packet header), one about every
    // 1 / (1024 * 10 Hz) = 97.66 us.
    EXPECT_TRUE(std::is_sorted(f.time.begin(), f.time.end()));
    std::vector<std::int64_t> stamps;
    for (const Packet& p : packets) {
      if (p.data.size() != 8448 || p.data[2] + 256 * p.data[3] != first_frame_id + f.seq) continue;
      for (int c = 0; c < 16; ++c) {
        std::int64_t t = 0;
        for (int b = 7; b >= 0; --b) t = t * 256 + p.data[32 + c * 524 + b];
        stamps.push_back(t);
      }
    }
    ASSERT_EQ(stamps.size(), 1024u);
    const std::int64_t t0 = *std::min_element(stamps.begin(), stamps.end());
    std::vector<float> columns(f.time);
    columns.erase(std::unique(columns.begin(), columns.end()), columns.end());
    EXPECT_GE(columns.size(), 1000u);
    for (const float t : columns) {
      const bool is_column_stamp = std::any_of(stamps.begin(), stamps.end(), [&](std::int64_t s) {
        return std::abs((s - t0) * 1e-9 - t) < 50e-9;
      });
      ASSERT_TRUE(is_column_stamp) << t;
    }
    for (std::size_t i = 1; i < columns.size(); ++i) {
      const double steps = (columns[i] - columns[i - 1]) / 97.656e-6;
      ASSERT_NEAR(steps, std::round(steps), 0.15) << "column " << i;
    }
    EXPECT_NEAR(f.time.back(), 1023 * 97.656e-6, 1e-4);
  }
  for (std::size_t i = 1; i < frames.size(); ++i)
    EXPECT_NEAR((frames[i].stamp_ns - frames[i - 1].stamp_ns) * 1e-9, 0.1, 1e-3);

  // Geometry: the frames registered pairwise move as the SDK's poses say (about 0.25 m in x).
  const auto poses = readKittiPoses(osFolder() / "OS-1-128_v2.3.0_1024x10_lb_n3_poses_kitti.txt");
  ASSERT_EQ(poses.size(), 3u);
  // Consecutive pairs and the first to the last frame.
  const std::vector<std::pair<std::size_t, std::size_t>> pairs = {{0, 1}, {1, 2}, {0, 2}};
  for (const auto& [i, j] : pairs) {
    // Registered as captured, then again deskewed with the velocity that gave.
    const double dt_frames = (frames[j].stamp_ns - frames[i].stamp_ns) * 1e-9;
    CloudRegistration reg = registerClouds(frames[j].points, frames[i].points);
    const Eigen::Vector3d velocity = reg.pose.translation() / dt_frames;
    reg = registerClouds(deskewed(frames[j], velocity), deskewed(frames[i], velocity));
    const Eigen::Isometry3d& ours = reg.pose;
    const Eigen::Isometry3d sdk = poses[i].inverse() * poses[j];
    const double dt = (ours.translation() - sdk.translation()).norm();
    const double dr = Eigen::AngleAxisd(ours.linear().transpose() * sdk.linear()).angle();
    std::cout << "frames " << i << "->" << j << ": ours " << ours.translation().transpose()
              << ", SDK " << sdk.translation().transpose() << " (differ " << dt << " m, "
              << dr * 180 / M_PI << " deg); " << 100 * reg.inlier_fraction
              << " % of the points within 5 cm of the other frame's surfaces\n";
    EXPECT_LT(dt, j - i == 1 ? 0.025 : 0.015);
    EXPECT_LT(dr, 0.2 * M_PI / 180);
    EXPECT_GT(reg.inlier_fraction, 0.6);
  }
}

}  // namespace
}  // namespace socc::sensors
