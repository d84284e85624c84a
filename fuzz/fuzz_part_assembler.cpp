// Parts of large messages as a LAN receiver gets them (socc/rpc/part_transport.hpp): the input
// is a sequence of records [2-byte big-endian length][encoded part_t], each decoded and fed to a
// PartAssembler with small limits while the clock advances, so stalls and give-ups happen too.
// A delivered message must have the size its parts announced; a NACK must list what it counts.
#include <chrono>
#include <cstddef>
#include <cstdint>

#include "socc/part_t.hpp"
#include "socc/rpc/part_assembler.hpp"
#include "socc/rpc/safe_decode.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > (1u << 20)) return 0;
  socc::rpc::PartAssemblerLimits limits;
  limits.max_message_bytes = 1 << 16;
  limits.max_transfers = 4;
  limits.max_nacks = 3;
  socc::rpc::PartAssembler assembler(limits);
  auto now = std::chrono::steady_clock::time_point{};
  std::size_t at = 0;
  while (at + 2 <= size) {
    const std::size_t n = (static_cast<std::size_t>(data[at]) << 8) | data[at + 1];
    at += 2;
    if (n > size - at) break;
    const auto part = socc::rpc::safeDecode<socc::part_t>(data + at, static_cast<int>(n));
    at += n;
    now += std::chrono::milliseconds(7);
    if (!part) continue;
    if (const auto whole = assembler.add(*part, now))
      if (whole->size() != static_cast<std::size_t>(part->total_size)) __builtin_trap();
    for (const auto& stalled : assembler.stalled(now))
      if (stalled.nack.num_missing != static_cast<std::int32_t>(stalled.nack.missing.size()) ||
          stalled.nack.missing.empty())
        __builtin_trap();
  }
  return 0;
}
