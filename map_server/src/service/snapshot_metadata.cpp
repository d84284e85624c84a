#include "snapshot_metadata.hpp"

#include <exception>
#include <string_view>

#include "socc/map_stats_t.hpp"
#include "socc/rpc/safe_decode.hpp"

namespace socc::service {
namespace {

// The counters follow the LCM message as a tagged text section. A trailer (rather than a new
// LCM field) keeps map_stats_t's fingerprint, so snapshots without counters stay readable.
constexpr std::string_view kCountersTag = "\nSOCC-AUTH-COUNTERS v1\n";

}  // namespace

std::string encodeSnapshotMetadata(const SnapshotMetadata& metadata) {
  map_stats_t message{};
  message.integrations = metadata.journal_sequence;
  message.num_robots = static_cast<std::int32_t>(metadata.robots.size());
  message.robots = metadata.robots;
  std::string blob(static_cast<std::size_t>(message.getEncodedSize()), '\0');
  message.encode(blob.data(), 0, static_cast<int>(blob.size()));
  if (!metadata.auth_counters.empty())
    blob += std::string(kCountersTag) + auth::serializeCounters(metadata.auth_counters);
  return blob;
}

std::optional<SnapshotMetadata> decodeSnapshotMetadata(const std::string& blob) {
  if (blob.empty()) return SnapshotMetadata{};
  std::size_t message_size = blob.size();
  std::string counters_text;
  if (const auto tag = blob.rfind(kCountersTag); tag != std::string::npos) {
    message_size = tag;
    counters_text = blob.substr(tag + kCountersTag.size());
  }
  const auto message = rpc::safeDecode<map_stats_t>(blob.data(), static_cast<int>(message_size));
  if (!message) return std::nullopt;
  SnapshotMetadata metadata{message->robots, message->integrations, {}};
  try {
    metadata.auth_counters = auth::parseCounters(counters_text);
  } catch (const std::exception&) {
    return std::nullopt;
  }
  return metadata;
}

}  // namespace socc::service
