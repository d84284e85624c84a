#include "gravity_reference.hpp"

#include <cmath>

namespace socc::consistency {

std::optional<GravityReference> gravityReference(const Eigen::Vector3d& up, double sigma) {
  const double norm = up.norm();
  if (!(sigma > 0.0) || !std::isfinite(sigma) || !std::isfinite(norm) || !(norm > 0.0))
    return std::nullopt;
  return GravityReference{up / norm, sigma};
}

}  // namespace socc::consistency
