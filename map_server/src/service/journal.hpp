#pragma once
// Write-ahead journal of accepted Integrate requests: an LCM log file (lcm-logplayer and
// lcm-logger compatible) whose first event records the snapshot sequence it continues from,
// followed by one event per accepted request (the encoded integrate_request_t). Entry i has
// the global sequence base + i + 1, so replay after a snapshot skips what it already covers.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string_view>
#include <vector>

namespace lcm {
class LogFile;
}

namespace socc::service {

/// When appended entries are forced to stable storage (fdatasync); docs/fleet.md has the cost.
/// Every mode writes each entry to the OS before append() returns, so kill -9 loses nothing.
enum class JournalSync {
  kNone,    // never: a power loss can lose entries the OS had not written yet
  kBatch,   // at sync(): the caller syncs once per group and acknowledges after it
  kAlways,  // in every append(), before it returns
};

/// "none", "batch", "always" -> the mode; nullopt for anything else.
std::optional<JournalSync> parseJournalSync(std::string_view name);
const char* journalSyncName(JournalSync sync);

struct JournalContents {
  std::int64_t base_sequence = 0;
  std::vector<std::vector<std::uint8_t>> requests;  // encoded integrate_request_t, in order
};

class Journal {
 public:
  /// Starts a fresh journal at file continuing after base_sequence (atomically replaces it).
  Journal(std::filesystem::path file, std::int64_t base_sequence,
          JournalSync sync = JournalSync::kBatch);
  ~Journal();
  Journal(const Journal&) = delete;
  Journal& operator=(const Journal&) = delete;

  /// Appends one encoded request and flushes it to the OS, so it survives kill -9; with
  /// kAlways also to stable storage. Throws std::runtime_error on I/O errors.
  void append(const std::uint8_t* encoded_request, std::size_t size);
  /// Forces the entries appended since the last sync to stable storage (kBatch; a no-op for
  /// kNone and when nothing is pending). Throws std::runtime_error when fdatasync fails.
  void sync();
  /// Drops all entries: the journal now continues after base_sequence (after a snapshot).
  /// The new file and its name are on stable storage before the old journal is replaced.
  void restart(std::int64_t base_sequence);

  JournalSync syncMode() const { return sync_; }
  /// fdatasync calls made for appended entries so far (the cost a mode pays).
  std::int64_t syncs() const { return syncs_; }

  const std::filesystem::path& file() const { return file_; }
  std::int64_t lastSequence() const { return base_sequence_ + entries_; }

  /// Reads a journal; a torn last event (crash while writing) ends the list. Throws
  /// std::runtime_error when the file is missing or is not a socc journal.
  static JournalContents read(const std::filesystem::path& file);

 private:
  std::filesystem::path file_;
  std::int64_t base_sequence_ = 0;
  std::int64_t entries_ = 0;
  JournalSync sync_ = JournalSync::kBatch;
  bool unsynced_ = false;  // entries appended since the last fdatasync
  std::int64_t syncs_ = 0;
  std::unique_ptr<lcm::LogFile> log_;
};

}  // namespace socc::service
