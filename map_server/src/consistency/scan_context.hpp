#pragma once
// A place descriptor of one scan (Scan Context, Kim & Kim, IROS 2018): the sensor's
// surroundings cut into rings (range) and sectors (azimuth), each bin holding the highest point
// above the sensor. It does not depend on the heading: turning the sensor shifts the sectors,
// so two scans are compared at every sector shift and the best shift is their relative yaw.
// The ring key (the share of occupied bins per ring) does not change with the heading either
// and ranks candidates before the full comparison.
#include <Eigen/Core>
#include <vector>

namespace socc::consistency {

struct ScanContextParams {
  int rings = 20;
  int sectors = 60;
  double max_range = 80.0;     // [m] points beyond are left out
  double height_offset = 2.0;  // [m] added to z so that bins below the sensor stay positive
};

class ScanContext {
 public:
  ScanContext() = default;
  /// The descriptor of points (sensor frame, z up).
  ScanContext(const std::vector<Eigen::Vector3f>& points, const ScanContextParams& params);

  /// Heading-invariant summary for candidate ranking (one value per ring).
  const Eigen::VectorXf& ringKey() const { return ring_key_; }

  struct Match {
    double distance = 1.0;  // 0 = identical, 1 = nothing alike
    double yaw = 0.0;       // [rad] heading of this scan's sensor in other's sensor frame
  };
  /// Mean cosine distance of the sectors at the best sector shift.
  Match compare(const ScanContext& other) const;

  bool empty() const { return bins_.size() == 0; }
  std::size_t bytes() const;

 private:
  Eigen::MatrixXf bins_;  // rings x sectors, max height (+ offset), 0 = empty
  Eigen::VectorXf ring_key_;
};

}  // namespace socc::consistency
