#pragma once
// Write-ahead journal of accepted Integrate requests: an LCM log file (lcm-logplayer and
// lcm-logger compatible) whose first event records the snapshot sequence it continues from,
// followed by one event per accepted request (the encoded integrate_request_t). Entry i has
// the global sequence base + i + 1, so replay after a snapshot skips what it already covers.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <vector>

namespace lcm {
class LogFile;
}

namespace socc::service {

struct JournalContents {
  std::int64_t base_sequence = 0;
  std::vector<std::vector<std::uint8_t>> requests;  // encoded integrate_request_t, in order
};

class Journal {
 public:
  /// Starts a fresh journal at file continuing after base_sequence (atomically replaces it).
  Journal(std::filesystem::path file, std::int64_t base_sequence);
  ~Journal();
  Journal(const Journal&) = delete;
  Journal& operator=(const Journal&) = delete;

  /// Appends one encoded request and flushes it to the OS, so it survives kill -9.
  /// Throws std::runtime_error on I/O errors.
  void append(const std::uint8_t* encoded_request, std::size_t size);
  /// Drops all entries: the journal now continues after base_sequence (after a snapshot).
  void restart(std::int64_t base_sequence);

  const std::filesystem::path& file() const { return file_; }
  std::int64_t lastSequence() const { return base_sequence_ + entries_; }

  /// Reads a journal; a torn last event (crash while writing) ends the list. Throws
  /// std::runtime_error when the file is missing or is not a socc journal.
  static JournalContents read(const std::filesystem::path& file);

 private:
  std::filesystem::path file_;
  std::int64_t base_sequence_ = 0;
  std::int64_t entries_ = 0;
  std::unique_ptr<lcm::LogFile> log_;
};

}  // namespace socc::service
