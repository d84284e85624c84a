#include "snapshot_metadata.hpp"

#include "socc/map_stats_t.hpp"
#include "socc/rpc/safe_decode.hpp"

namespace socc::service {

std::string encodeSnapshotMetadata(const SnapshotMetadata& metadata) {
  map_stats_t message{};
  message.integrations = metadata.journal_sequence;
  message.num_robots = static_cast<std::int32_t>(metadata.robots.size());
  message.robots = metadata.robots;
  std::string blob(static_cast<std::size_t>(message.getEncodedSize()), '\0');
  message.encode(blob.data(), 0, static_cast<int>(blob.size()));
  return blob;
}

std::optional<SnapshotMetadata> decodeSnapshotMetadata(const std::string& blob) {
  if (blob.empty()) return SnapshotMetadata{};
  const auto message = rpc::safeDecode<map_stats_t>(blob.data(), static_cast<int>(blob.size()));
  if (!message) return std::nullopt;
  return SnapshotMetadata{message->robots, message->integrations};
}

}  // namespace socc::service
