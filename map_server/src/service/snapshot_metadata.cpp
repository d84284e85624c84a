#include "snapshot_metadata.hpp"

#include <exception>
#include <string>
#include <string_view>
#include <vector>

#include "socc/map_stats_t.hpp"
#include "socc/rpc/safe_decode.hpp"

namespace socc::service {
namespace {

// Sections follow the LCM message, each behind a tag. A trailer (rather than new map_stats_t
// fields) keeps map_stats_t's fingerprint, so older snapshots stay readable.
constexpr std::string_view kHistoriesTag = "\nSOCC-POSE-HISTORIES v1\n";  // count, then messages
constexpr std::string_view kCountersTag = "\nSOCC-AUTH-COUNTERS v1\n";

template <typename Message>
void appendEncoded(std::string& blob, const Message& message) {
  const std::size_t at = blob.size();
  blob.resize(at + static_cast<std::size_t>(message.getEncodedSize()));
  message.encode(blob.data() + at, 0, static_cast<int>(blob.size() - at));
}

// The histories section, blob[pos, end): tag, decimal count, newline, then that many
// pose_history_t messages filling it exactly.
bool decodeHistories(const std::string& blob, std::size_t pos, std::size_t end,
                     std::vector<pose_history_t>& out) {
  if (blob.compare(pos, kHistoriesTag.size(), kHistoriesTag) != 0) return false;
  pos += kHistoriesTag.size();
  const std::size_t newline = blob.find('\n', pos);
  if (newline == std::string::npos || newline >= end || newline == pos || newline - pos > 9)
    return false;
  const std::string count_text = blob.substr(pos, newline - pos);
  if (count_text.find_first_not_of("0123456789") != std::string::npos) return false;
  const std::size_t count = std::stoul(count_text);
  pos = newline + 1;
  for (std::size_t i = 0; i < count; ++i) {
    std::size_t used = 0;
    auto h = rpc::safeDecodePrefix<pose_history_t>(blob.data() + pos, static_cast<int>(end - pos),
                                                   &used);
    if (!h) return false;
    out.push_back(std::move(*h));
    pos += used;
  }
  return pos == end;
}

}  // namespace

std::string encodeSnapshotMetadata(const SnapshotMetadata& metadata) {
  map_stats_t message{};
  message.integrations = metadata.journal_sequence;
  message.num_robots = static_cast<std::int32_t>(metadata.robots.size());
  message.robots = metadata.robots;
  std::string blob;
  appendEncoded(blob, message);
  if (!metadata.histories.empty()) {
    blob += std::string(kHistoriesTag) + std::to_string(metadata.histories.size()) + "\n";
    for (const pose_history_t& h : metadata.histories) appendEncoded(blob, h);
  }
  if (!metadata.auth_counters.empty())
    blob += std::string(kCountersTag) + auth::serializeCounters(metadata.auth_counters);
  return blob;
}

std::optional<SnapshotMetadata> decodeSnapshotMetadata(const std::string& blob) {
  if (blob.empty()) return SnapshotMetadata{};
  std::size_t end = blob.size();  // of the binary part
  std::string counters_text;
  if (const auto tag = blob.rfind(kCountersTag); tag != std::string::npos) {
    end = tag;
    counters_text = blob.substr(tag + kCountersTag.size());
  }
  std::size_t pos = 0;
  const auto message = rpc::safeDecodePrefix<map_stats_t>(blob.data(), static_cast<int>(end), &pos);
  if (!message) return std::nullopt;
  SnapshotMetadata metadata{message->robots, {}, message->integrations, {}};
  if (pos < end && !decodeHistories(blob, pos, end, metadata.histories)) return std::nullopt;
  try {
    metadata.auth_counters = auth::parseCounters(counters_text);
  } catch (const std::exception&) {
    return std::nullopt;
  }
  return metadata;
}

}  // namespace socc::service
