#include "grid_rebuild.hpp"

namespace socc::consistency {

bool integrateScan(map::SemanticOccupancyMap& map, const Eigen::Isometry3d& pose,
                   const KeyframeScan& scan) {
  if (scan.empty()) return false;
  const LabeledCloud cloud = scan.cloud();
  if (!map.validate(pose, cloud).empty()) return false;
  map.integrate(pose, cloud);
  return true;
}

double poseShift(const Eigen::Isometry3d& from, const Eigen::Isometry3d& to, double lever) {
  const double angle = Eigen::AngleAxisd(from.linear().transpose() * to.linear()).angle();
  return (to.translation() - from.translation()).norm() + angle * lever;
}

}  // namespace socc::consistency
