#include "socc/odom/se3.hpp"

#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/Lie/SE.h>

#include <Eigen/SVD>
#include <cmath>

namespace socc::odom {

Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

namespace {

// Left Jacobian of SO(3): maps the translational part of a twist to the translation of exp.
Eigen::Matrix3d leftJacobian(const Eigen::Vector3d& omega) {
  const double theta = omega.norm();
  const Eigen::Matrix3d w = skew(omega);
  if (theta < 1e-9) return Eigen::Matrix3d::Identity() + 0.5 * w;
  const double t2 = theta * theta;
  return Eigen::Matrix3d::Identity() + (1.0 - std::cos(theta)) / t2 * w +
         (theta - std::sin(theta)) / (t2 * theta) * w * w;
}

}  // namespace

Eigen::Isometry3d expSe3(const Vector6d& xi) {
  const Eigen::Vector3d rho = xi.head<3>();
  const Eigen::Vector3d omega = xi.tail<3>();
  const double theta = omega.norm();
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  if (theta > 1e-12) out.linear() = Eigen::AngleAxisd(theta, omega / theta).toRotationMatrix();
  out.translation() = leftJacobian(omega) * rho;
  return out;
}

Vector6d logSe3(const Eigen::Isometry3d& pose) {
  const Eigen::AngleAxisd aa(pose.linear());
  const Eigen::Vector3d omega = aa.angle() * aa.axis();
  Vector6d xi;
  xi.head<3>() = leftJacobian(omega).inverse() * pose.translation();
  xi.tail<3>() = omega;
  return xi;
}

Eigen::Isometry3d applyIncrement(const Vector6d& dx, const Eigen::Isometry3d& pose) {
  mrpt::poses::Lie::SE<3>::tangent_vector v;
  for (int i = 0; i < 6; ++i) v[i] = dx[i];
  const mrpt::poses::CPose3D delta = mrpt::poses::Lie::SE<3>::exp(v);
  mrpt::math::CMatrixDouble44 m;
  delta.getHomogeneousMatrix(m);
  Eigen::Isometry3d d = Eigen::Isometry3d::Identity();
  d.matrix() = m.asEigen();
  return orthonormalized(d * pose);
}

Eigen::Isometry3d orthonormalized(const Eigen::Isometry3d& pose) {
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  // Polar decomposition: U V^T is the rotation nearest to the linear part (Frobenius norm).
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(pose.linear(),
                                              Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d u = svd.matrixU();
  if ((u * svd.matrixV().transpose()).determinant() < 0.0) u.col(2) *= -1.0;
  out.linear() = u * svd.matrixV().transpose();
  out.translation() = pose.translation();
  return out;
}

}  // namespace socc::odom
