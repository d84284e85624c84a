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
// fields) keeps map_stats_t's fingerprint; when map_stats_t or robot_state_t itself grows, the
// previous layout gets a reader of its own (decodeStatsWithoutVersion,
// decodeStatsWithoutTracking), so older snapshots stay readable.
constexpr std::string_view kHistoriesTag = "\nSOCC-POSE-HISTORIES v1\n";  // count, then messages
constexpr std::string_view kCountersTag = "\nSOCC-AUTH-COUNTERS v1\n";
constexpr std::string_view kCorrectionsTag = "\nSOCC-ROBOT-CORRECTIONS v1\n";

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

// Big-endian reader of LCM encodings that never reads past end.
class LcmReader {
 public:
  LcmReader(const std::string& blob, std::size_t end)
      : data_(blob.data()), end_(static_cast<int>(end)) {}
  bool int64(std::int64_t& v) {
    return step(__int64_t_decode_array(data_, pos_, end_ - pos_, &v, 1));
  }
  bool int32(std::int32_t& v) {
    return step(__int32_t_decode_array(data_, pos_, end_ - pos_, &v, 1));
  }
  bool skip(int bytes) { return bytes <= end_ - pos_ && step(bytes); }
  bool string(std::string& s) {  // int32 length including the NUL, then the bytes
    std::int32_t length = 0;
    if (!int32(length) || length < 1 || length > end_ - pos_) return false;
    s.assign(data_ + pos_, static_cast<std::size_t>(length - 1));
    return step(length);
  }
  template <typename Message>
  bool message(Message& m) {
    return step(m._decodeNoHash(data_, pos_, end_ - pos_));
  }
  std::size_t pos() const { return static_cast<std::size_t>(pos_); }

 private:
  bool step(int bytes) {
    if (bytes < 0) return false;
    pos_ += bytes;
    return true;
  }
  const char* data_;
  int end_;
  int pos_ = 0;
};

// The head of map_stats_t as snapshots wrote it before server_version: the fingerprint of
// then, utime .. map_version (8 fields of 8 bytes), integrations (the journal sequence),
// integrations_per_s .. auth_failures (4 fields), num_robots.
bool readStatsHead(LcmReader& r, std::int64_t fingerprint, SnapshotMetadata& out,
                   std::int32_t& num_robots) {
  std::int64_t found = 0;
  return r.int64(found) && found == fingerprint && r.skip(64) && r.int64(out.journal_sequence) &&
         r.skip(32) && r.int32(num_robots) && num_robots >= 0;
}

// map_stats_t as snapshots wrote it before it had server_version (its LCM fingerprint then):
// the robots are today's robot_state_t. Sets pos past it.
bool decodeStatsWithoutVersion(const std::string& blob, std::size_t end, SnapshotMetadata& out,
                               std::size_t& pos) {
  constexpr auto kFingerprint = static_cast<std::int64_t>(0xaac20648c2eb2350ULL);
  LcmReader r(blob, end);
  std::int32_t num_robots = 0;
  if (!readStatsHead(r, kFingerprint, out, num_robots)) return false;
  for (std::int32_t i = 0; i < num_robots; ++i) {
    robot_state_t s{};
    if (!r.message(s)) return false;
    out.robots.push_back(std::move(s));
  }
  pos = r.pos();
  return true;
}

// map_stats_t as snapshots wrote it before robot_state_t had the tracking fields (its LCM
// fingerprint then): same layout, each robot only up to last_pose. Sets pos past it.
bool decodeStatsWithoutTracking(const std::string& blob, std::size_t end, SnapshotMetadata& out,
                                std::size_t& pos) {
  constexpr auto kFingerprint = static_cast<std::int64_t>(0xde2b7c79f2ca2e59ULL);
  LcmReader r(blob, end);
  std::int32_t num_robots = 0;
  if (!readStatsHead(r, kFingerprint, out, num_robots)) return false;
  for (std::int32_t i = 0; i < num_robots; ++i) {
    robot_state_t s{};
    if (!r.string(s.robot_id) || !r.int64(s.last_seq) || !r.int64(s.last_scan_utime) ||
        !r.int64(s.integrations) || !r.message(s.last_pose))
      return false;
    out.robots.push_back(std::move(s));
  }
  pos = r.pos();
  return true;
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
  if (!metadata.corrections.empty()) blob += std::string(kCorrectionsTag) + metadata.corrections;
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
  SnapshotMetadata metadata;
  if (const auto tag = blob.rfind(kCorrectionsTag, end); tag != std::string::npos) {
    metadata.corrections =
        blob.substr(tag + kCorrectionsTag.size(), end - tag - kCorrectionsTag.size());
    end = tag;
  }
  std::size_t pos = 0;
  if (const auto message =
          rpc::safeDecodePrefix<map_stats_t>(blob.data(), static_cast<int>(end), &pos)) {
    metadata.robots = message->robots;
    metadata.journal_sequence = message->integrations;
  } else if (!decodeStatsWithoutVersion(blob, end, metadata, pos) &&
             !decodeStatsWithoutTracking(blob, end, metadata, pos)) {
    return std::nullopt;
  }
  if (pos < end && !decodeHistories(blob, pos, end, metadata.histories)) return std::nullopt;
  try {
    metadata.auth_counters = auth::parseCounters(counters_text);
  } catch (const std::exception&) {
    return std::nullopt;
  }
  return metadata;
}

}  // namespace socc::service
