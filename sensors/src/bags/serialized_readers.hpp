#pragma once
// The two serializations of ROS messages in bags, one small reader each, with the same member
// functions so that a message parser is written once (a template over the reader):
//   Ros1Reader: ROS 1 (little-endian, packed, uint32 length-prefixed strings and sequences;
//               time = uint32 sec, uint32 nsec; Header starts with uint32 seq).
//   CdrReader:  OMG CDR as ROS 2 writes it: a 4-byte encapsulation header (0x00 0x00 big-endian,
//               0x00 0x01 little-endian), then the message with every primitive aligned to its
//               size relative to the first byte after that header; strings carry their
//               terminating NUL in the length; time = int32 sec, uint32 nanosec.
// Both throw FormatError on a read past the end or an impossible length.
#include <cstdint>
#include <string>

#include "bags/byte_view.hpp"

namespace socc::sensors::bags {

/// std_msgs/Header without the ROS 1 seq (which nothing here uses).
struct MessageHeader {
  std::int64_t stamp_ns = 0;
  std::string frame_id;
};

class Ros1Reader {
 public:
  explicit Ros1Reader(ByteView message) : cursor_(message) {}

  template <class T>
  T read() {
    return cursor_.read<T>();
  }
  /// uint8[n] (fixed-size arrays have no length prefix).
  ByteView bytes(std::size_t n) { return cursor_.take(n); }
  /// A sequence's element count; throws if count * min_element_bytes cannot fit.
  std::uint32_t sequenceLength(std::size_t min_element_bytes);
  std::string string() { return cursor_.string32(); }
  std::int64_t time();
  MessageHeader header();
  std::size_t remaining() const { return cursor_.remaining(); }

 private:
  ByteCursor cursor_;
};

class CdrReader {
 public:
  /// Reads the encapsulation header; throws on a kind this reader does not decode.
  explicit CdrReader(ByteView message);

  template <class T>
  T read() {
    align(sizeof(T));
    const ByteView b = body_.sub(pos_, sizeof(T));
    pos_ += sizeof(T);
    return loadValue<T>(b.data, big_endian_);
  }
  ByteView bytes(std::size_t n) {
    const ByteView b = body_.sub(pos_, n);
    pos_ += n;
    return b;
  }
  std::uint32_t sequenceLength(std::size_t min_element_bytes);
  std::string string();
  std::int64_t time();
  MessageHeader header();
  std::size_t remaining() const { return body_.size - pos_; }

 private:
  void align(std::size_t n);

  ByteView body_;  // after the encapsulation header: alignment is relative to its start
  std::size_t pos_ = 0;
  bool big_endian_ = false;
};

}  // namespace socc::sensors::bags
