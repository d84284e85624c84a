// Point lookups into the grid (e.g. which side of a surface was seen free).
#include "map_impl.hpp"

namespace socc::map {

double SemanticOccupancyMap::occupancyAt(const Eigen::Vector3d& p) const {
  if (!p.allFinite() || p.cwiseAbs().maxCoeff() > impl_->config.max_abs_coordinate) return -1.0;
  const VoxelIndex v = impl_->grid.indexOf(p);
  const Block* block = impl_->grid.find(blockOf(v));
  const int local = localOf(v);
  if (block == nullptr || !block->observed[static_cast<std::size_t>(local)]) return -1.0;
  return probability(block->log_odds[static_cast<std::size_t>(local)]);
}

}  // namespace socc::map
