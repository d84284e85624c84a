#include "bags/chunked_bag_reader.hpp"

namespace socc::sensors::bags {

std::optional<BagMessage> ChunkedBagReader::next() {
  while (true) {
    if (chunk_) {
      if (std::optional<BagMessage> m = nextInChunk()) return m;
      continue;
    }
    if (ended_) return std::nullopt;
    if (std::optional<BagMessage> m = nextTopLevel()) return m;
  }
}

std::optional<BagMessage> ChunkedBagReader::nextInChunk() {
  try {
    while (!chunk_cursor_->done()) {
      if (std::optional<BagMessage> m = nextChunkRecord(*chunk_cursor_)) return m;
    }
  } catch (const FormatError& e) {
    damaged(e.what());
  }
  chunk_cursor_.reset();
  chunk_.reset();
  return std::nullopt;
}

void ChunkedBagReader::damaged(const std::string& what) {
  if (damaged_chunks_++ == 0) first_damage_ = what;
}

std::string ChunkedBagReader::problems() const {
  std::string p;
  if (damaged_chunks_ > 0) {
    p += std::to_string(damaged_chunks_) + " damaged chunks skipped (first: " + first_damage_ +
         ")\n";
  }
  if (!stop_reason_.empty()) p += "reading stopped: " + stop_reason_ + "\n";
  return p + containerProblems();
}

}  // namespace socc::sensors::bags
