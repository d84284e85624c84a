#pragma once
// Validation of a PCD file's text header before PCL parses it: PCL 1.13's PCDReader
// segfaults on some malformed files (e.g. a header without FIELDS). Used by every PCD reader
// (socc-to-lcmlog, odom_client --pcd-dir).
#include <filesystem>

namespace socc {

/// Throws std::runtime_error naming the problem unless the header has known keys only, the
/// FIELDS/SIZE/TYPE/COUNT lists agree, WIDTH * HEIGHT == POINTS, DATA is ascii, binary or
/// binary_compressed and, for binary data, the file holds POINTS points.
void checkPcdHeader(const std::filesystem::path& file);

}  // namespace socc
