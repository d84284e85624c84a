// PCD export of occupied voxels (binary PointXYZRGBL). The only translation unit that
// includes PCL, which is slow to compile.
#include <pcl/io/pcd_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <fstream>
#include <stdexcept>

#include "map_impl.hpp"

namespace socc::map {

std::int64_t SemanticOccupancyMap::exportPcd(const std::filesystem::path& file,
                                             double occupancy_threshold) const {
  const Impl& m = *impl_;
  pcl::PointCloud<pcl::PointXYZRGBL> cloud;
  m.forEachObserved([&](const VoxelIndex& v, float log_odds, const VoxelStats* stats) {
    if (probability(log_odds) < occupancy_threshold) return;
    const Eigen::Vector3d c = m.grid.centre(v);
    const std::uint8_t label = stats != nullptr ? stats->label : std::uint8_t{kUnlabeled};
    const Rgb rgb = label != kUnlabeled ? classColor(label) : Rgb{128, 128, 128};
    pcl::PointXYZRGBL p;
    p.x = static_cast<float>(c.x());
    p.y = static_cast<float>(c.y());
    p.z = static_cast<float>(c.z());
    p.r = rgb.r;
    p.g = rgb.g;
    p.b = rgb.b;
    p.a = 255;
    p.label = label;
    cloud.push_back(p);
  });
  cloud.width = static_cast<std::uint32_t>(cloud.size());
  cloud.height = 1;
  cloud.is_dense = true;
  if (cloud.empty()) {
    // PCL refuses to write empty clouds; an empty map is still a valid export.
    std::ofstream out(file);
    out << "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z rgb label\n"
           "SIZE 4 4 4 4 4\nTYPE F F F U U\nCOUNT 1 1 1 1 1\nWIDTH 0\nHEIGHT 1\n"
           "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 0\nDATA ascii\n";
    if (!out) throw std::runtime_error("pcd export: cannot write " + file.string());
    return 0;
  }
  if (pcl::io::savePCDFileBinary(file.string(), cloud) != 0)
    throw std::runtime_error("pcd export: cannot write " + file.string());
  return static_cast<std::int64_t>(cloud.size());
}

}  // namespace socc::map
