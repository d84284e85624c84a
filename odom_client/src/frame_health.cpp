#include "socc/odom/frame_health.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <sstream>

namespace socc::odom {
namespace {

// The smallest eigenvalue of the point-to-plane system's translation block, with its direction:
// about how many (weighted) planar correspondences pin the least constrained direction.
void weakestDirection(const Eigen::Matrix3d& block, FrameHealth& h) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(block);  // ascending
  h.weakest_constraint = std::max(0.0, eig.eigenvalues()[0]);
  h.weakest_direction = eig.eigenvectors().col(0);
}

void fail(FrameHealth& h, const std::string& why) {
  if (h.problem.empty()) h.problem = why;
}

std::string format(const char* what, double value, const char* op, double limit) {
  std::ostringstream out;
  out.precision(3);
  out << what << ' ' << value << ' ' << op << ' ' << limit;
  return out.str();
}

constexpr double kDeg = M_PI / 180.0;

}  // namespace

FrameHealth judgeRegistration(const RegistrationResult& r, std::size_t points, double sigma,
                              const OdomConfig& limits) {
  FrameHealth h;
  h.inlier_fraction = points > 0 ? static_cast<double>(r.correspondences()) / points : 0.0;
  h.residual_ratio = sigma > 0.0 ? r.rms_residual / sigma : 0.0;
  weakestDirection(r.planar_information.topLeftCorner<3, 3>(), h);
  h.degenerate = h.weakest_constraint < limits.min_constraint;
  if (h.inlier_fraction < limits.min_inlier_fraction)
    fail(h, format("inlier fraction", h.inlier_fraction, "<", limits.min_inlier_fraction));
  if (h.residual_ratio > limits.max_residual_ratio)
    fail(h, format("residual/sigma", h.residual_ratio, ">", limits.max_residual_ratio));
  return h;
}

void judgeMotion(FrameHealth& h, const Vector6d& twist, const Vector6d* previous_twist, double dt,
                 const OdomConfig& limits) {
  h.linear_speed = twist.head<3>().norm();
  h.angular_speed = twist.tail<3>().norm();
  std::string& surprise = h.surprise;
  const auto note = [&surprise](const std::string& what) {
    if (surprise.empty()) surprise = what;
  };
  if (h.linear_speed > limits.max_linear_speed)
    note(format("speed [m/s]", h.linear_speed, ">", limits.max_linear_speed));
  if (h.angular_speed > limits.max_angular_speed * kDeg)
    note(format("turn rate [deg/s]", h.angular_speed / kDeg, ">", limits.max_angular_speed));
  if (previous_twist != nullptr && dt > 0.0) {
    h.linear_acceleration = (twist.head<3>() - previous_twist->head<3>()).norm() / dt;
    h.angular_acceleration = (twist.tail<3>() - previous_twist->tail<3>()).norm() / dt;
    if (h.linear_acceleration > limits.max_linear_acceleration)
      note(format("acceleration [m/s^2]", h.linear_acceleration, ">",
                  limits.max_linear_acceleration));
    if (h.angular_acceleration > limits.max_angular_acceleration * kDeg)
      note(format("angular acceleration [deg/s^2]", h.angular_acceleration / kDeg, ">",
                  limits.max_angular_acceleration));
  }
  // A degenerate registration slides along its weakest direction unchecked: there the motion
  // model is the only evidence, and the estimate contradicts it.
  if (h.degenerate && !h.surprise.empty()) fail(h, "degenerate and " + h.surprise);
}

}  // namespace socc::odom
