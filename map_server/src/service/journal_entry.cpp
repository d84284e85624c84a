#include "journal_entry.hpp"

#include <utility>

#include "socc/rpc/safe_decode.hpp"

namespace socc::service {

integrate_request_t fromPreGravity(integrate_request_v1_t old) {
  integrate_request_t r{};  // gravity_up 0, gravity_sigma 0: no gravity reference
  r.header = std::move(old.header);
  r.seq = old.seq;
  r.scan_utime = old.scan_utime;
  r.sensor_pose = old.sensor_pose;
  r.num_points = old.num_points;
  r.xyz_resolution = old.xyz_resolution;
  r.xyz = std::move(old.xyz);
  r.num_labels = old.num_labels;
  r.label = std::move(old.label);
  r.num_times = old.num_times;
  r.time = std::move(old.time);
  return r;
}

std::optional<integrate_request_t> decodeJournalEntry(const std::uint8_t* data, std::size_t size) {
  const int n = static_cast<int>(size);
  if (auto request = rpc::safeDecode<integrate_request_t>(data, n)) return request;
  // Each form carries its own fingerprint: the old bytes never decode as the new type.
  if (auto old = rpc::safeDecode<integrate_request_v1_t>(data, n))
    return fromPreGravity(std::move(*old));
  return std::nullopt;
}

}  // namespace socc::service
