#include "wire_guard.hpp"

#include <cstdint>

namespace socc::service {
namespace {

// Big-endian reader over a byte span that never reads past the end.
class WireCursor {
 public:
  WireCursor(const void* data, int size)
      : data_(static_cast<const std::uint8_t*>(data)), size_(size) {}

  bool skip(std::int64_t bytes) {
    if (bytes < 0 || bytes > size_ - pos_) return false;
    pos_ += static_cast<int>(bytes);
    return true;
  }
  bool readInt32(std::int32_t& value) {
    if (size_ - pos_ < 4) return false;
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v = (v << 8) | data_[pos_ + i];
    value = static_cast<std::int32_t>(v);
    pos_ += 4;
    return true;
  }
  /// An array of count elements of element_size bytes, count read from the wire.
  bool skipArray(std::int64_t element_size) {
    std::int32_t count = 0;
    return readInt32(count) && count >= 0 && skip(count * element_size);
  }
  /// LCM strings: int32 length including the terminating NUL, then the bytes.
  bool skipString() {
    std::int32_t length = 0;
    return readInt32(length) && length >= 1 && skip(length);
  }

 private:
  const std::uint8_t* data_;
  int size_;
  int pos_ = 0;
};

std::string walkHeader(WireCursor& cursor) {
  if (!cursor.skip(8 + 8)) return "truncated request header";  // type hash, request_id
  if (!cursor.skipString() || !cursor.skipString()) return "bad string length in request header";
  if (!cursor.skip(8 + 8)) return "truncated request header";  // utime, auth_counter
  if (!cursor.skipArray(1)) return "bad mac_len in request header";
  return {};
}

}  // namespace

std::string checkRequestHeaderWire(const void* data, int size) {
  if (data == nullptr || size <= 0) return "empty message";
  WireCursor cursor(data, size);
  return walkHeader(cursor);
}

std::string checkIntegrateWire(const void* data, int size) {
  if (data == nullptr || size <= 0) return "empty message";
  WireCursor cursor(data, size);
  if (std::string why = walkHeader(cursor); !why.empty()) return why;
  constexpr std::int64_t kPoseBytes = 7 * 8;  // pose3d_t: 3 + 4 doubles
  if (!cursor.skip(8 + 8 + kPoseBytes)) return "truncated integrate request";
  // num_points, xyz_resolution (float), xyz[3][num_points]: 3 rows of num_points int16.
  std::int32_t points = 0;
  if (!cursor.readInt32(points) || points < 0 || !cursor.skip(4) ||
      !cursor.skip(std::int64_t{points} * 3 * 2))
    return "num_points does not match the message size";
  if (!cursor.skipArray(1)) return "num_labels does not match the message size";
  if (!cursor.skipArray(4)) return "num_times does not match the message size";
  if (!cursor.skip(4 * 4)) return "truncated integrate request (gravity_up, gravity_sigma)";
  return {};
}

}  // namespace socc::service
