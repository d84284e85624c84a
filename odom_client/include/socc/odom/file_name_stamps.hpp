#pragma once
// Scan times written into file names, as recorders that dump one file per scan name them:
// "1317354748.213624.pcd" (seconds), "1317354748213624000.pcd" (an integer count of seconds,
// milliseconds, microseconds or nanoseconds since the epoch, told apart by its size). Frame
// numbers ("000123.pcd") and other names are no stamps.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <vector>

namespace socc::odom {

/// [us] the stamp in name's stem, or nullopt when it holds none.
std::optional<std::int64_t> fileNameStamp(const std::filesystem::path& name);

/// The stamps of every file [us], when each has one and they increase strictly; else empty.
std::vector<std::int64_t> fileNameStamps(const std::vector<std::filesystem::path>& files);

}  // namespace socc::odom
