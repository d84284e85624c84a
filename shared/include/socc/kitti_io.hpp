#pragma once
// Readers and writers of the KITTI / SemanticKITTI odometry layout:
//   velodyne/NNNNNN.bin  float32 x, y, z, reflectance per point
//   labels/NNNNNN.label  uint32 per point (lower 16 bits: semantic id, upper: instance)
//   poses.txt            3x4 row-major per line;  calib.txt with a "Tr:" line;  times.txt
// All readers throw std::runtime_error with the file name and the reason on bad input.
#include <Eigen/Geometry>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "socc/point_cloud.hpp"

namespace socc {

using Poses = std::vector<Eigen::Isometry3d>;

/// Poses with what is known of them: the odometry's output and the trajectories socc-eval
/// reads. stamps [s] and seqs (scan sequence numbers) are empty when unknown (KITTI files).
struct Trajectory {
  Poses poses;
  std::vector<double> stamps;
  std::vector<std::int64_t> seqs;
};

/// Reads x, y, z of a KITTI .bin (4 floats per point); reflectance is returned if asked.
Points readKittiBin(const std::filesystem::path& file, std::vector<float>* reflectance = nullptr);
/// Reads a raw float32 x, y, z file (3 floats per point).
Points readXyzBin(const std::filesystem::path& file);
/// Reads a raw float32 array (e.g. per-point times).
std::vector<float> readFloatBin(const std::filesystem::path& file);
/// Reads raw uint32 SemanticKITTI labels (unmapped).
std::vector<std::uint32_t> readSemanticKittiLabels(const std::filesystem::path& file);
/// KITTI poses: one 3x4 row-major matrix per line.
Poses readKittiPoses(const std::filesystem::path& file);
/// TUM poses: "t x y z qx qy qz qw" per line ('#' comments); stamps go to *stamps.
Poses readTumPoses(const std::filesystem::path& file, std::vector<double>* stamps = nullptr);
/// The velodyne-to-camera "Tr:" transform of a KITTI calib.txt (also accepts a file whose only
/// content is the 12 numbers). Throws if absent.
Eigen::Isometry3d readKittiCalibTr(const std::filesystem::path& file);
/// One timestamp [s] per line.
std::vector<double> readTimes(const std::filesystem::path& file);

void writeKittiBin(const std::filesystem::path& file, const Points& points,
                   const std::vector<float>* reflectance = nullptr);
void writeSemanticKittiLabels(const std::filesystem::path& file,
                              const std::vector<std::uint32_t>& labels);
void writeKittiPoses(const std::filesystem::path& file, const Poses& poses);
void writeTumPoses(const std::filesystem::path& file, const Poses& poses,
                   const std::vector<double>& stamps);

/// Frame files of a KITTI-layout directory: sorted velodyne/*.bin and the matching
/// labels/*.label (empty path where absent).
struct KittiSequence {
  std::filesystem::path root;
  std::vector<std::filesystem::path> scans;
  std::vector<std::filesystem::path> labels;  // same size as scans; empty entries allowed
};
KittiSequence listKittiSequence(const std::filesystem::path& root);

/// KITTI GT is in the left-camera frame: T_lidar = Tr^-1 * T_cam * Tr.
Poses cameraToLidarPoses(const Poses& camera_poses, const Eigen::Isometry3d& tr);
/// root/poses.txt (KITTI GT, camera frame) in the LiDAR frame, using root/calib.txt's Tr.
Poses readKittiLidarPoses(const std::filesystem::path& root);
/// KITTI odometry sequence `sequence`'s GT in the LiDAR frame from a folder of the benchmark's
/// GT as it is published (gt_dir/poses/NN.txt and the two calibrations the sequences share:
/// gt_dir/calib_00-02.txt for 00-02, gt_dir/calib_04-10_Tr.txt for 04-10). Throws for other
/// sequences (03's calibration is not among them) and on missing files.
Poses readKittiGtLidarPoses(const std::filesystem::path& gt_dir, int sequence);

}  // namespace socc
