#pragma once
// SE(3) exponential/logarithm on 6-vectors (translation part first, then rotation).
// expSe3/logSe3: the true group exponential (screw motion), used to interpolate motion within
// a sweep. applyIncrement: MRPT's Lie-group SE(3) exp, used for ICP updates.
#include <Eigen/Geometry>

namespace socc::odom {

using Vector6d = Eigen::Matrix<double, 6, 1>;

Eigen::Isometry3d expSe3(const Vector6d& xi);
Vector6d logSe3(const Eigen::Isometry3d& pose);

/// exp(dx) * pose with dx = (translation, rotation) through mrpt::poses::Lie::SE<3>::exp.
Eigen::Isometry3d applyIncrement(const Vector6d& dx, const Eigen::Isometry3d& pose);

/// The nearest pure rigid transform. Isometry3d::inverse() assumes an exact rotation, so
/// round-off left in a pose would otherwise grow frame by frame through the velocity model.
Eigen::Isometry3d orthonormalized(const Eigen::Isometry3d& pose);

/// [v]x: the cross-product matrix, skew(a) * b = a x b.
Eigen::Matrix3d skew(const Eigen::Vector3d& v);

}  // namespace socc::odom
