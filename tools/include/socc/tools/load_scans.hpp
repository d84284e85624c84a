#pragma once
// The scans and trajectories the simulated robots of socc-loadtest send: real KITTI scans
// from a directory or a deterministic synthetic LiDAR-like scan of KITTI size, and straight
// trajectories offset per robot so the robots map disjoint areas (as a real fleet would).
#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "socc/point_cloud.hpp"

namespace socc::tools {

/// Scans shared read-only by all robot threads.
class ScanSet {
 public:
  /// Every velodyne/*.bin of dir (with labels/*.label when present). Throws when empty.
  static ScanSet fromKitti(const std::filesystem::path& dir);
  /// One synthetic scan of `points` points: 64 beams over 360 deg hitting a ground plane and
  /// walls, labelled road / building. Same input, same scan.
  static ScanSet synthetic(std::size_t points);

  const LabeledCloud& scan(std::size_t frame) const { return scans_[frame % scans_.size()]; }
  std::size_t size() const { return scans_.size(); }
  std::size_t averagePoints() const;

 private:
  std::vector<LabeledCloud> scans_;
};

/// Robot r drives along +x at `step` metres per scan, on its own lane 200 m from the others.
Eigen::Isometry3d robotPose(int robot, std::int64_t frame, double step = 1.0);

}  // namespace socc::tools
