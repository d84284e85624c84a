#pragma once
// Decoding of untrusted LCM bytes. The generated decode() reports truncation by a negative
// return value but can also throw (negative string lengths -> std::length_error, huge array
// counts -> std::bad_alloc); both must end as "not decodable", never as a crash.
#include <exception>
#include <optional>

namespace socc::rpc {

template <typename Message>
std::optional<Message> safeDecode(const void* data, int size) {
  if (data == nullptr || size <= 0) return std::nullopt;
  Message message;
  try {
    // A message must use all the bytes: trailing garbage means a different or damaged type.
    if (message.decode(data, 0, size) != size) return std::nullopt;
  } catch (const std::exception&) {
    return std::nullopt;
  }
  return message;
}

}  // namespace socc::rpc
