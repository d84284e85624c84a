#pragma once
// gRPC-style outcome of a handler: a reply_header_t code and a human-readable message.
#include <cstdint>
#include <string>

#include "socc/reply_header_t.hpp"

namespace socc::service {

struct Status {
  std::int8_t code = reply_header_t::OK;
  std::string message;

  bool ok() const { return code == reply_header_t::OK; }
  static Status invalid(std::string m) { return {reply_header_t::INVALID_ARGUMENT, std::move(m)}; }
  static Status notFound(std::string m) { return {reply_header_t::NOT_FOUND, std::move(m)}; }
  static Status exhausted(std::string m) {
    return {reply_header_t::RESOURCE_EXHAUSTED, std::move(m)};
  }
  static Status failedPrecondition(std::string m) {
    return {reply_header_t::FAILED_PRECONDITION, std::move(m)};
  }
  static Status internal(std::string m) { return {reply_header_t::INTERNAL, std::move(m)}; }
  static Status unauthenticated(std::string m) {
    return {reply_header_t::UNAUTHENTICATED, std::move(m)};
  }
};

/// Writes status into a reply's header; ids and time are filled by the router.
template <typename Reply>
Reply& setStatus(Reply& reply, const Status& status) {
  reply.header.status = status.code;
  reply.header.message = status.message;
  return reply;
}

}  // namespace socc::service
