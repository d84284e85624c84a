#include "bags/serialized_readers.hpp"

namespace socc::sensors::bags {

namespace {

std::uint32_t checkedSequenceLength(std::uint32_t count, std::size_t min_element_bytes,
                                    std::size_t remaining) {
  if (min_element_bytes > 0 && count > remaining / min_element_bytes) {
    throw FormatError("sequence of " + std::to_string(count) + " elements in " +
                      std::to_string(remaining) + " bytes");
  }
  return count;
}

std::int64_t messageStampNs(std::int64_t sec, std::uint32_t nsec) {
  if (nsec >= 1'000'000'000u) throw FormatError("time with " + std::to_string(nsec) + " ns");
  return sec * 1'000'000'000 + nsec;
}

}  // namespace

std::uint32_t Ros1Reader::sequenceLength(std::size_t min_element_bytes) {
  return checkedSequenceLength(read<std::uint32_t>(), min_element_bytes, remaining());
}

std::int64_t Ros1Reader::time() {
  const auto sec = read<std::uint32_t>();
  return messageStampNs(sec, read<std::uint32_t>());
}

MessageHeader Ros1Reader::header() {
  read<std::uint32_t>();  // seq
  MessageHeader h;
  h.stamp_ns = time();
  h.frame_id = string();
  return h;
}

CdrReader::CdrReader(ByteView message) {
  const ByteView encapsulation = message.sub(0, 4);
  if (encapsulation.data[0] != 0 || encapsulation.data[1] > 1) {
    throw FormatError("CDR encapsulation " + std::to_string(encapsulation.data[0]) + "," +
                      std::to_string(encapsulation.data[1]) +
                      " (only plain CDR, big- or little-endian, is decoded)");
  }
  big_endian_ = encapsulation.data[1] == 0;
  body_ = message.sub(4, message.size - 4);
}

void CdrReader::align(std::size_t n) {
  const std::size_t padded = (pos_ + n - 1) / n * n;
  body_.sub(0, padded);  // throws when the padding runs past the end
  pos_ = padded;
}

std::uint32_t CdrReader::sequenceLength(std::size_t min_element_bytes) {
  return checkedSequenceLength(read<std::uint32_t>(), min_element_bytes, remaining());
}

std::string CdrReader::string() {
  const auto n = read<std::uint32_t>();
  std::string s = bytes(n).str();
  if (!s.empty() && s.back() == '\0') s.pop_back();
  return s;
}

std::int64_t CdrReader::time() {
  const auto sec = read<std::int32_t>();
  return messageStampNs(sec, read<std::uint32_t>());
}

MessageHeader CdrReader::header() {
  MessageHeader h;
  h.stamp_ns = time();
  h.frame_id = string();
  return h;
}

}  // namespace socc::sensors::bags
