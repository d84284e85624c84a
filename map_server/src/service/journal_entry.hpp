#pragma once
// Decoding a journal entry (an encoded INTEGRATE) of this or an older server: the current
// integrate_request_t, its pre-epoch form integrate_request_v2_t (docs/lcm.md "Which frame a pose
// is in") or its pre-gravity form integrate_request_v1_t (docs/lcm.md "Gravity reference"), read
// as a request without what its server did not know yet.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <type_traits>
#include <utility>

#include "socc/integrate_request_t.hpp"
#include "socc/integrate_request_v1_t.hpp"
#include "socc/integrate_request_v2_t.hpp"

namespace socc::service {

/// The request of an older entry: the same fields; gravity_sigma 0 (no reference) for a
/// pre-gravity one, map_epoch 0 (the frame the server last told the robot) for both.
template <class Older>
integrate_request_t upgraded(Older old) {
  integrate_request_t r{};
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
  if constexpr (std::is_same_v<Older, integrate_request_v2_t>) {
    for (int i = 0; i < 3; ++i) r.gravity_up[i] = old.gravity_up[i];
    r.gravity_sigma = old.gravity_sigma;
  }
  return r;
}

/// nullopt when the bytes are none of the forms.
std::optional<integrate_request_t> decodeJournalEntry(const std::uint8_t* data, std::size_t size);

}  // namespace socc::service
