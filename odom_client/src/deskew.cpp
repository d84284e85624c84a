#include "socc/odom/deskew.hpp"

#include <tbb/parallel_for.h>

#include "socc/odom/se3.hpp"

namespace socc::odom {

LabeledCloud deskew(const LabeledCloud& cloud, const Eigen::Isometry3d& frame_motion,
                    double frame_period, double reference_time) {
  LabeledCloud out = cloud;
  if (!cloud.hasTimes() || !(frame_period > 0.0)) return out;
  const Vector6d xi = logSe3(frame_motion) / frame_period;  // twist per second
  tbb::parallel_for(std::size_t{0}, cloud.size(), [&](std::size_t i) {
    const double dt = static_cast<double>(cloud.times[i]) - reference_time;
    out.points[i] = (expSe3(dt * xi) * cloud.points[i].cast<double>()).cast<float>();
  });
  return out;
}

}  // namespace socc::odom
