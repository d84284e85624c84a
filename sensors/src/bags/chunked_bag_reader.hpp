#pragma once
// The reading loop of a container that keeps messages in chunks (compressed record buffers)
// between top-level records: MCAP (ROS 1 bags are read by rosbag_storage). Messages come from the
// open chunk until it is used up, then from the top level, which may open the next chunk. A damaged
// chunk is skipped and counted; damage at the top level ends the reading (stop()). Each container
// says how to read its top level and its chunk records.
#include <cstdint>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "bags/bag_reader.hpp"
#include "bags/byte_view.hpp"

namespace socc::sensors::bags {

class ChunkedBagReader : public BagReader {
 public:
  const std::vector<TopicInfo>& topics() const override { return topics_; }
  void select(std::size_t topic) override { selected_ = topic; }
  std::optional<BagMessage> next() override;
  /// Damaged chunks and why reading stopped, then the container's own counts.
  std::string problems() const override;

 protected:
  /// The next top-level record: a message of the selected topic, or nullopt (a declaration, a
  /// chunk opened with openChunk, the end: end() or stop()).
  virtual std::optional<BagMessage> nextTopLevel() = 0;
  /// Reads one record of the open chunk: a message of the selected topic, or nullopt. Throws
  /// FormatError on damage (the rest of the chunk is skipped).
  virtual std::optional<BagMessage> nextChunkRecord(ByteCursor& records) = 0;
  /// The container's own problem lines (empty: none).
  virtual std::string containerProblems() const { return {}; }

  /// Opens a chunk with the records that decode() returns (FormatError: counted as damaged).
  template <class Decode>
  void openChunk(Decode&& decode) {
    try {
      chunk_ = decode();
      chunk_cursor_.emplace(ByteView(*chunk_));
    } catch (const FormatError& e) {
      damaged(e.what());
    }
  }
  void end() { ended_ = true; }
  /// Ends the reading because of damage at the top level.
  void stop(const std::string& reason) {
    stop_reason_ = reason;
    ended_ = true;
  }
  bool selectedOther(std::size_t topic) const { return selected_ && topic != *selected_; }
  /// True when the container's index lists the chunk at `offset` (chunk_streams: the channel or
  /// connection ids with messages in each chunk) with streams of other topics only, so that it
  /// need not be decompressed. Unknown chunks and streams are never skipped.
  template <class Id>
  bool otherTopicsOnly(std::uint64_t offset,
                       const std::unordered_map<std::uint64_t, std::vector<Id>>& chunk_streams,
                       const std::unordered_map<Id, std::size_t>& stream_topic) const {
    if (!selected_) return false;
    const auto it = chunk_streams.find(offset);
    if (it == chunk_streams.end() || it->second.empty()) return false;
    for (const Id id : it->second) {
      const auto topic = stream_topic.find(id);
      if (topic == stream_topic.end() || topic->second == *selected_) return false;
    }
    return true;
  }

  std::vector<TopicInfo> topics_;
  std::optional<std::size_t> selected_;

 private:
  std::optional<BagMessage> nextInChunk();
  void damaged(const std::string& what);

  bool ended_ = false;
  std::optional<std::vector<std::uint8_t>> chunk_;
  std::optional<ByteCursor> chunk_cursor_;
  std::uint64_t damaged_chunks_ = 0;
  std::string first_damage_;
  std::string stop_reason_;
};

}  // namespace socc::sensors::bags
