#include "bags/record_file.hpp"

#include <stdexcept>

namespace socc::sensors::bags {

RecordFile::RecordFile(const std::filesystem::path& file) : path_(file) {
  std::error_code ec;
  size_ = std::filesystem::file_size(file, ec);
  in_.open(file, std::ios::binary);
  if (ec || !in_) throw std::runtime_error(file.string() + ": cannot open");
}

std::vector<std::uint8_t> RecordFile::read(std::uint64_t offset, std::uint64_t n) {
  if (offset > size_ || n > size_ - offset) {
    throw FormatError("record of " + std::to_string(n) + " bytes at " + std::to_string(offset) +
                      " runs past the end of the file (" + std::to_string(size_) + " bytes)");
  }
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(n));
  in_.clear();
  in_.seekg(static_cast<std::streamoff>(offset));
  in_.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(n));
  if (!in_) throw FormatError("read error at " + std::to_string(offset));
  return bytes;
}

}  // namespace socc::sensors::bags
