// Export of occupied voxels to OctoMap (.bt: OcTree binary; .ot: ColorOcTree with class
// colours). Same resolution and voxel alignment (OctoMap keys are floor(x / res) + 2^15), so
// each voxel maps to exactly one leaf.
#include <octomap/ColorOcTree.h>
#include <octomap/OcTree.h>

#include <stdexcept>

#include "map_impl.hpp"

namespace socc::map {
namespace {

struct ExportVoxel {
  Eigen::Vector3d centre;
  float log_odds;
  std::uint8_t label;
};

template <typename Tree, typename SetExtra>
std::int64_t fill(Tree& tree, const MapConfig& config, const std::vector<ExportVoxel>& voxels,
                  SetExtra&& set_extra) {
  tree.setClampingThresMin(config.clamp_min);
  tree.setClampingThresMax(config.clamp_max);
  tree.setOccupancyThres(config.occupancy_threshold);
  // Exported voxels must read as occupied in OctoMap too, whatever the export threshold.
  const float min_occupied = static_cast<float>(logit(config.occupancy_threshold)) + 1e-3f;
  std::int64_t n = 0;
  for (const ExportVoxel& v : voxels) {
    octomap::OcTreeKey key;
    const octomap::point3d p(static_cast<float>(v.centre.x()), static_cast<float>(v.centre.y()),
                             static_cast<float>(v.centre.z()));
    if (!tree.coordToKeyChecked(p, key)) continue;  // outside OctoMap's 2^16-voxel range
    auto* node = tree.setNodeValue(key, std::max(v.log_odds, min_occupied), true);
    set_extra(node, v.label);
    ++n;
  }
  tree.updateInnerOccupancy();
  return n;
}

}  // namespace

std::int64_t SemanticOccupancyMap::exportOctomap(const std::filesystem::path& file,
                                                 double occupancy_threshold) const {
  const Impl& m = *impl_;
  const std::string ext = file.extension().string();
  std::vector<ExportVoxel> voxels;
  m.forEachObserved([&](const VoxelIndex& v, float log_odds, const VoxelStats* stats) {
    if (probability(log_odds) >= occupancy_threshold)
      voxels.push_back(
          {m.grid.centre(v), log_odds, stats != nullptr ? stats->label : std::uint8_t{0}});
  });
  std::int64_t n = 0;
  bool ok = false;
  if (ext == ".bt") {
    octomap::OcTree tree(m.config.voxel_size);
    n = fill(tree, m.config, voxels, [](octomap::OcTreeNode*, std::uint8_t) {});
    ok = tree.writeBinary(file.string());
  } else if (ext == ".ot") {
    octomap::ColorOcTree tree(m.config.voxel_size);
    n = fill(tree, m.config, voxels, [](octomap::ColorOcTreeNode* node, std::uint8_t label) {
      const Rgb c = label != kUnlabeled ? classColor(label) : Rgb{128, 128, 128};
      node->setColor(c.r, c.g, c.b);
    });
    ok = tree.write(file.string());
  } else {
    throw std::runtime_error("octomap export: unknown extension '" + ext + "' (use .bt or .ot)");
  }
  if (!ok) throw std::runtime_error("octomap export: cannot write " + file.string());
  return n;
}

}  // namespace socc::map
