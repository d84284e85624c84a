#pragma once
// PCD / PLY files (through PCL; PCL stays inside point_cloud_file.cpp because it compiles slowly).
// x, y, z are required; an optional "label" field holds raw SemanticKITTI ids (lower 16 bits,
// mapped with socc::mapSemanticKittiLabel) and an optional "time" or "t" field per-point times [s].
#include <filesystem>

#include "socc/point_cloud.hpp"

namespace socc::odom {

/// Throws std::runtime_error naming the file on a missing/unreadable file or missing x/y/z.
LabeledCloud loadPointCloudFile(const std::filesystem::path& file);

/// True for .pcd and .ply (case-insensitive).
bool isPointCloudFile(const std::filesystem::path& file);

}  // namespace socc::odom
