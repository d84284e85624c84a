// The only socc translation unit of the tools that includes PCL (slow to compile).
#include <pcl/PCLPointCloud2.h>
#include <pcl/conversions.h>
#include <pcl/exceptions.h>
#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>

#include <cmath>
#include <stdexcept>

#include "socc/labels.hpp"
#include "socc/pcd_header.hpp"
#include "socc/tools/scan_directory.hpp"

namespace socc::tools {

namespace {

bool hasField(const pcl::PCLPointCloud2& blob, const char* name) {
  for (const auto& f : blob.fields)
    if (f.name == name) return true;
  return false;
}
}  // namespace

ScanFrame readPcdScan(const std::filesystem::path& file) {
  checkPcdHeader(file);
  pcl::PCLPointCloud2 blob;
  try {
    if (pcl::io::loadPCDFile(file.string(), blob) < 0)
      throw std::runtime_error(file.string() + ": not a readable PCD file");
  } catch (const pcl::PCLException& e) {
    throw std::runtime_error(file.string() + ": " + e.what());
  }
  if (!hasField(blob, "x") || !hasField(blob, "y") || !hasField(blob, "z"))
    throw std::runtime_error(file.string() + ": PCD has no x, y, z fields");

  // Convert per field of interest; fields of another data type stay 0 (PCL warns).
  pcl::PointCloud<pcl::PointXYZ> xyz;
  pcl::fromPCLPointCloud2(blob, xyz);
  pcl::PointCloud<pcl::PointXYZI> with_intensity;
  const bool intensity = hasField(blob, "intensity");
  if (intensity) pcl::fromPCLPointCloud2(blob, with_intensity);
  pcl::PointCloud<pcl::PointXYZL> with_label;
  const bool label = hasField(blob, "label");
  if (label) pcl::fromPCLPointCloud2(blob, with_label);

  ScanFrame frame;
  for (std::size_t i = 0; i < xyz.size(); ++i) {
    const pcl::PointXYZ& p = xyz[i];
    // Organized clouds mark missing returns with NaN: they are not measurements.
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) continue;
    frame.cloud.points.emplace_back(p.x, p.y, p.z);
    if (intensity) frame.intensity.push_back(with_intensity[i].intensity);
    if (label) frame.cloud.labels.push_back(mapSemanticKittiLabel(with_label[i].label));
  }
  return frame;
}

}  // namespace socc::tools
