#pragma once
// The consistency store: an append-only file beside the map's snapshot (docs/consistency.md,
// "Durability") of what the consistency service cannot recompute from the snapshot and the
// journal: its keyframes (with their matching points and rebuild scans), accepted closures,
// rebuilt grids' poses and checkpoint marks, each mark preceded by the keyframes still waiting
// for the worker then (as observed). Each record is written once, by the service's worker (the
// marks and waiting keyframes by the map's thread), flushed to the OS before the call returns (kill
// -9 loses nothing written) and, with sync, to stable storage. A processed keyframe's scan is never
// rewritten: a checkpoint of the map adds a mark of a few bytes and the clouds of the keyframes
// waiting then, full or reduced on arrival (once each; the worker stores them again when it
// processed them).
//
// Layout: the header "SOCC-CONSISTENCY-STORE", a format version (uint32) and the base (uint8:
// 1 = the store began on a grid it did not see built); then records {uint32 marker, uint8
// type, uint64 size, payload, uint32 CRC32 of type and payload}, little-endian. A torn or
// corrupt record (a crash while writing, a damaged disk) ends the store: it and everything
// after it are dropped with a message, and the next writer cuts the file there.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "store_records.hpp"

namespace socc::consistency {

struct StoreContents {
  bool foreign_base = false;  // began on a grid whose scans it does not hold
  std::vector<StoredKeyframe> keyframes;
  std::vector<StoredClosure> closures;
  std::vector<StoredRebuild> rebuilds;
  std::vector<StoredCheckpoint> checkpoints;
  std::vector<StoredWaiting> waiting;  // in the order written (may repeat a stored keyframe)
  std::uint64_t valid_bytes = 0;       // the file's length up to the last whole record
  std::string problem;                 // what was dropped from the end ("" when nothing)
};

class KeyframeStore {
 public:
  /// A new, empty store at file, replacing any old one atomically. Throws std::runtime_error.
  static std::unique_ptr<KeyframeStore> create(const std::filesystem::path& file, bool foreign_base,
                                               bool sync);
  /// Appends to the store read as contents, cutting off what it dropped. Throws.
  static std::unique_ptr<KeyframeStore> resume(const std::filesystem::path& file,
                                               const StoreContents& contents, bool sync);
  /// Reads a store. Throws std::runtime_error when the file is missing, unreadable, not a
  /// consistency store or of another format version; a torn or corrupt tail is only dropped.
  static StoreContents read(const std::filesystem::path& file);

  ~KeyframeStore();
  KeyframeStore(const KeyframeStore&) = delete;
  KeyframeStore& operator=(const KeyframeStore&) = delete;

  // Thread-safe. A failed write (disk full) is reported once on stderr and stops the store:
  // every later record is left out, so what it holds stays a prefix of what happened.
  void add(RecordType type, const std::string& payload);
  /// Appends records in order with one flush and one fdatasync (a checkpoint's waiting
  /// keyframes and its mark: one disk sync on the map's thread, not one per keyframe).
  void add(const std::vector<std::pair<RecordType, std::string>>& records);
  bool failed() const;
  std::uint64_t bytes() const;
  const std::filesystem::path& file() const { return file_; }

 private:
  KeyframeStore(std::filesystem::path file, std::FILE* out, std::uint64_t bytes, bool sync);
  /// A record as it is in the file: marker, type, size, payload, checksum.
  static std::string framed(RecordType type, const std::string& payload);
  /// Appends bytes, flushed (and synced), unless the store failed before; a failure stops it.
  void write(const std::string& bytes);

  std::filesystem::path file_;
  bool sync_ = true;
  mutable std::mutex mutex_;
  std::FILE* out_ = nullptr;
  std::uint64_t bytes_ = 0;
  bool failed_ = false;
};

}  // namespace socc::consistency
