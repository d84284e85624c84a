#pragma once
// The real KITTI scans of the data folder's kitti_pairs (SOCC_SHARED_DATA_DIR, see
// ../shared/data/README) and their GT in the LiDAR frame: one reader for the tests that use them.
#include <Eigen/Geometry>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "socc/kitti_io.hpp"
#include "socc/point_cloud.hpp"

namespace socc::test {

inline std::filesystem::path sharedData() {
  return SOCC_SHARED_DATA_DIR;
}

/// kitti_pairs/<sequence>/velodyne: absent when the data folder is.
inline std::filesystem::path kittiPairsDir(const std::string& sequence) {
  return sharedData() / "kitti_pairs" / sequence / "velodyne";
}

/// One scan of kitti_pairs/<sequence>, unlabelled.
inline LabeledCloud kittiPairScan(const std::string& sequence, int frame) {
  char name[16];
  std::snprintf(name, sizeof(name), "%06d.bin", frame);
  LabeledCloud cloud;
  cloud.points = readKittiBin(kittiPairsDir(sequence) / name);
  return cloud;
}

/// The GT poses of frames of KITTI sequence `sequence`, in the LiDAR frame.
inline Poses kittiGt(int sequence, const std::vector<int>& frames) {
  const Poses all = readKittiGtLidarPoses(sharedData() / "kitti_gt", sequence);
  Poses out;
  for (const int f : frames) out.push_back(all.at(static_cast<std::size_t>(f)));
  return out;
}

}  // namespace socc::test
