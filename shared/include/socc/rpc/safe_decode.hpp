#pragma once
// Decoding of untrusted LCM bytes. The generated decode() reports truncation by a negative
// return value but can also throw (negative string lengths -> std::length_error, huge array
// counts -> std::bad_alloc); both must end as "not decodable", never as a crash.
#include <cstddef>
#include <exception>
#include <optional>

namespace socc::rpc {

/// Decodes a Message at the start of data, where more bytes may follow (a message inside a
/// larger blob); *used is set to its encoded size.
template <typename Message>
std::optional<Message> safeDecodePrefix(const void* data, int size, std::size_t* used) {
  if (data == nullptr || size <= 0) return std::nullopt;
  Message message;
  try {
    const int n = message.decode(data, 0, size);
    if (n <= 0) return std::nullopt;
    *used = static_cast<std::size_t>(n);
  } catch (const std::exception&) {
    return std::nullopt;
  }
  return message;
}

template <typename Message>
std::optional<Message> safeDecode(const void* data, int size) {
  std::size_t used = 0;
  auto message = safeDecodePrefix<Message>(data, size, &used);
  // A message must use all the bytes: trailing garbage means a different or damaged type.
  if (message && used != static_cast<std::size_t>(size)) return std::nullopt;
  return message;
}

}  // namespace socc::rpc
