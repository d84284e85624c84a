#pragma once
// Random access to the bytes of a container file (MCAP): reads of known length at
// known offsets, a FormatError when they would run past the end (a truncated file).
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <vector>

#include "bags/byte_view.hpp"

namespace socc::sensors::bags {

class RecordFile {
 public:
  /// Throws std::runtime_error naming the file when it cannot be opened.
  explicit RecordFile(const std::filesystem::path& file);

  std::uint64_t size() const { return size_; }
  /// Bytes [offset, offset + n).
  std::vector<std::uint8_t> read(std::uint64_t offset, std::uint64_t n);
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  std::ifstream in_;
  std::uint64_t size_ = 0;
};

}  // namespace socc::sensors::bags
