#pragma once
// Scan preprocessing: sanity checks and the range filter.
#include <string>

#include "socc/point_cloud.hpp"

namespace socc::odom {

/// Empty when the cloud's labels/times are sized like its points and every label is a valid
/// class id; otherwise the reason. (Non-finite points are not an error: rangeFilter drops them.)
std::string checkCloud(const LabeledCloud& cloud);

/// Keeps finite points with min_range <= |p| <= max_range (labels and times follow).
/// Non-finite times count as non-finite points.
LabeledCloud rangeFilter(const LabeledCloud& cloud, double min_range, double max_range);

/// Raises every point's elevation by `radians` (range and azimuth kept): the correction of a
/// sensor whose vertical angles are all off by the same amount, e.g. KITTI's HDL-64 (its points
/// lie ~0.2 deg too low, which bends the ground into a shallow cone).
void correctElevation(LabeledCloud& cloud, double radians);

/// All labels set to 0 (unlabeled): the --no-semantics mode.
void dropLabels(LabeledCloud& cloud);

}  // namespace socc::odom
