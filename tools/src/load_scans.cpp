#include "socc/tools/load_scans.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "socc/kitti_io.hpp"
#include "socc/labels.hpp"

namespace socc::tools {

ScanSet ScanSet::fromKitti(const std::filesystem::path& dir) {
  const KittiSequence sequence = listKittiSequence(dir);
  ScanSet set;
  for (std::size_t i = 0; i < sequence.scans.size(); ++i) {
    LabeledCloud cloud;
    cloud.points = readKittiBin(sequence.scans[i]);
    if (!sequence.labels[i].empty())
      for (const std::uint32_t raw : readSemanticKittiLabels(sequence.labels[i]))
        cloud.labels.push_back(mapSemanticKittiLabel(raw));
    if (!cloud.consistent()) cloud.labels.clear();  // a label file of another scan: drop it
    set.scans_.push_back(std::move(cloud));
  }
  if (set.scans_.empty()) throw std::runtime_error("no velodyne/*.bin scans in " + dir.string());
  return set;
}

ScanSet ScanSet::synthetic(std::size_t points) {
  // Like a 64-beam spinning LiDAR 1.73 m above a road between two building rows 15 m to the
  // sides: beams below the horizon hit the ground, the others a wall (or nothing beyond 80 m).
  constexpr int kBeams = 64;
  constexpr double kSensorHeight = 1.73, kWallDistance = 15.0, kMaxRange = 80.0;
  const std::size_t columns = std::max<std::size_t>(1, points / kBeams);
  LabeledCloud cloud;
  cloud.points.reserve(points);
  cloud.labels.reserve(points);
  for (std::size_t i = 0; i < points; ++i) {
    const double azimuth =
        2.0 * M_PI * static_cast<double>(i / kBeams) / static_cast<double>(columns);
    const double elevation =
        (-24.8 + 26.8 * static_cast<double>(i % kBeams) / (kBeams - 1)) * M_PI / 180.0;
    const Eigen::Vector3d dir(std::cos(elevation) * std::cos(azimuth),
                              std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
    const double to_ground = dir.z() < 0 ? kSensorHeight / -dir.z() : kMaxRange;
    const double to_wall = std::abs(dir.y()) > 1e-6 ? kWallDistance / std::abs(dir.y()) : kMaxRange;
    const double range = std::min({to_ground, to_wall, kMaxRange});
    cloud.points.push_back((range * dir).cast<float>());
    cloud.labels.push_back(to_ground <= to_wall ? kRoad : kBuilding);
  }
  ScanSet set;
  set.scans_.push_back(std::move(cloud));
  return set;
}

std::size_t ScanSet::averagePoints() const {
  std::size_t total = 0;
  for (const auto& s : scans_) total += s.size();
  return scans_.empty() ? 0 : total / scans_.size();
}

Eigen::Isometry3d robotPose(int robot, std::int64_t frame, double step) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(step * static_cast<double>(frame), 200.0 * robot, 0.0);
  return pose;
}

}  // namespace socc::tools
