#pragma once
// Bounds-checked access to the bytes of containers and serialized messages. Every reader of
// untrusted bytes in the bag code goes through ByteView / ByteCursor, so an out-of-range length
// is a thrown FormatError, never a read past the buffer.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace socc::sensors::bags {

/// Malformed container or message bytes (truncated record, impossible length...).
class FormatError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A non-owning range of bytes (C++17 has no std::span).
struct ByteView {
  const std::uint8_t* data = nullptr;
  std::size_t size = 0;

  ByteView() = default;
  ByteView(const std::uint8_t* d, std::size_t n) : data(d), size(n) {}
  template <class Container>
  explicit ByteView(const Container& c) : data(c.data()), size(c.size()) {}

  /// Bytes [offset, offset + n); throws when they are not all inside.
  ByteView sub(std::size_t offset, std::size_t n) const {
    if (offset > size || n > size - offset) {
      throw FormatError("range " + std::to_string(offset) + "+" + std::to_string(n) + " outside " +
                        std::to_string(size) + " bytes");
    }
    return {data + offset, n};
  }
  std::string str() const { return std::string(reinterpret_cast<const char*>(data), size); }
};

/// The bytes of a string (no terminating zero).
inline ByteView textBytes(const std::string& s) {
  return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()};
}

/// A trivially copyable value stored in little- (or big-) endian byte order at p.
template <class T>
T loadValue(const std::uint8_t* p, bool big_endian) {
  static_assert(std::is_trivially_copyable_v<T>);
  std::uint8_t b[sizeof(T)];
  std::memcpy(b, p, sizeof(T));
  if (big_endian) {  // the machine is little-endian (x86-64, arm64 Linux)
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
  }
  T v;
  std::memcpy(&v, b, sizeof(T));
  return v;
}

/// Sequential little-endian reads from a ByteView (MCAP records, ROS 1 frames).
class ByteCursor {
 public:
  explicit ByteCursor(ByteView bytes) : bytes_(bytes) {}

  template <class T>
  T read() {
    const ByteView b = take(sizeof(T));
    return loadValue<T>(b.data, false);
  }
  ByteView take(std::size_t n) {
    const ByteView b = bytes_.sub(pos_, n);
    pos_ += n;
    return b;
  }
  /// uint32 length + bytes (MCAP strings and byte arrays).
  std::string string32() { return take(read<std::uint32_t>()).str(); }
  ByteView bytes32() { return take(read<std::uint32_t>()); }
  ByteView bytes64() {
    const auto n = read<std::uint64_t>();
    if (n > remaining()) throw FormatError("length " + std::to_string(n) + " past the end");
    return take(static_cast<std::size_t>(n));
  }
  std::size_t remaining() const { return bytes_.size - pos_; }
  std::size_t position() const { return pos_; }
  bool done() const { return pos_ == bytes_.size; }

 private:
  ByteView bytes_;
  std::size_t pos_ = 0;
};

}  // namespace socc::sensors::bags
