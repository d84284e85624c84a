#pragma once
// gravity.txt of a KITTI-layout directory (socc-sim writes it, odom_client reads it): one line
// per frame, "ux uy uz sigma_rad": the unit up vector in the sensor frame at the frame's time
// (times.txt, the pose of poses.txt) and the 1-sigma of its direction [rad]; sigma 0: no
// reference for that frame.
#include <filesystem>
#include <optional>
#include <vector>

#include "socc/gravity_reference.hpp"

namespace socc {

/// A vector whose length is off by more than this from 1 is an error, not a rounding.
inline constexpr double kGravityUnitTolerance = 1e-3;

/// One entry per line; nullopt where sigma is 0. Up vectors are normalized. Throws
/// std::runtime_error naming the file and line on a malformed line (not 4 numbers, a non-finite
/// value, a negative sigma, a vector not of unit length within kGravityUnitTolerance).
std::vector<std::optional<GravityReference>> readGravityFile(const std::filesystem::path& file);

/// Writes one line per entry (nullopt: "0 0 1 0"). Throws std::runtime_error when it cannot.
void writeGravityFile(const std::filesystem::path& file,
                      const std::vector<std::optional<GravityReference>>& entries);

}  // namespace socc
