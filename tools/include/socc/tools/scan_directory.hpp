#pragma once
// A directory of recorded scans, as read by socc-to-lcmlog:
//   KITTI layout: velodyne/NNNNNN.bin, optional labels/NNNNNN.label (SemanticKITTI, mapped to
//                 classes 0..19), optional point_times/NNNNNN.bin (float32 per point [s])
//   PCD layout:   *.pcd files (fields x y z, optional intensity and label)
// and in both an optional times.txt (one scan time [s] per line, indexed by frame number).
#include <cstdint>
#include <filesystem>
#include <vector>

#include "socc/point_cloud.hpp"

namespace socc::tools {

enum class ScanFormat { kKitti, kPcd };

struct ScanDirectory {
  ScanFormat format = ScanFormat::kKitti;
  std::filesystem::path root;
  std::vector<std::filesystem::path> scans;        // sorted by name
  std::vector<std::filesystem::path> labels;       // per scan; empty path where absent
  std::vector<std::filesystem::path> point_times;  // per scan; empty path where absent
  std::vector<double> scan_times;                  // per scan [s] from times.txt; empty if absent
};

/// One loaded scan: points with optional labels (classes 0..19) and per-point times, and
/// optional intensities (KITTI reflectance / PCD intensity).
struct ScanFrame {
  LabeledCloud cloud;
  std::vector<float> intensity;  // empty or one per point
};

/// Detects the layout and lists the scans. Throws std::runtime_error naming the problem
/// (no scans, unreadable times.txt, times.txt without a line for some scan, ...).
ScanDirectory openScanDirectory(const std::filesystem::path& root);

/// Loads scan i. Throws std::runtime_error when a file is corrupt or its label/time count
/// differs from its point count.
ScanFrame loadScan(const ScanDirectory& dir, std::size_t i);

/// Reads one PCD file (PCL; the only translation unit that includes PCL headers).
ScanFrame readPcdScan(const std::filesystem::path& file);

}  // namespace socc::tools
