#pragma once
// Little-endian byte buffer writer and bounds-checked reader for the snapshot format.
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace socc::map {

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "snapshot format assumes little endian");

class ByteWriter {
 public:
  template <typename T>
  void put(const T& v) {
    static_assert(std::is_arithmetic_v<T>);
    bytes_.append(reinterpret_cast<const char*>(&v), sizeof(T));
  }
  void putBytes(const std::string& s) {
    put<std::uint64_t>(s.size());
    bytes_.append(s);
  }
  const std::string& bytes() const { return bytes_; }

 private:
  std::string bytes_;
};

/// Every read checks the remaining size: a truncated or lying file throws, never overreads.
class ByteReader {
 public:
  ByteReader(const char* data, std::size_t size) : data_(data), size_(size) {}
  template <typename T>
  T get() {
    static_assert(std::is_arithmetic_v<T>);
    need(sizeof(T));
    T v;
    std::memcpy(&v, data_ + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  std::string getBytes() {
    const auto n = get<std::uint64_t>();
    need(n);
    std::string s(data_ + pos_, static_cast<std::size_t>(n));
    pos_ += static_cast<std::size_t>(n);
    return s;
  }
  std::size_t remaining() const { return size_ - pos_; }

 private:
  void need(std::uint64_t n) const {
    if (n > size_ - pos_) throw std::runtime_error("truncated data");
  }
  const char* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

}  // namespace socc::map
