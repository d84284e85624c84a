// Snapshots and the write-ahead journal (issue 6: the map survives kill -9).
#include <stdexcept>

#include "journal_entry.hpp"
#include "map_service.hpp"
#include "snapshot_metadata.hpp"
#include "socc/progress_bar.hpp"

namespace socc::service {

void MapService::saveSnapshot(const std::filesystem::path& file) const {
  SnapshotMetadata metadata;
  metadata.robots = robots_.states();
  metadata.histories = robots_.histories();
  metadata.journal_sequence = integrations_;
  if (replay_guard_ != nullptr) metadata.auth_counters = replay_guard_->counters();
  metadata.corrections = corrections_.serialize();
  map_.save(file, encodeSnapshotMetadata(metadata));
}

void MapService::loadSnapshot(const std::filesystem::path& file) {
  std::string blob;
  map::SemanticOccupancyMap loaded = map::SemanticOccupancyMap::load(file, &blob);
  const auto metadata = decodeSnapshotMetadata(blob);
  if (!metadata)
    throw std::runtime_error(file.string() + ": snapshot metadata (robot states) is corrupt");
  if (loaded.config().voxel_size != map_.config().voxel_size)
    throw std::runtime_error(
        file.string() + ": voxel size " + std::to_string(loaded.config().voxel_size) +
        " differs from the server's " + std::to_string(map_.config().voxel_size));
  RobotCorrections corrections;
  if (!corrections.parse(metadata->corrections))
    throw std::runtime_error(file.string() + ": snapshot metadata (robot corrections) is corrupt");
  // Commit only after everything was read and checked: a bad file changes nothing.
  map_ = std::move(loaded);
  robots_.assign(metadata->robots, metadata->histories);
  corrections_ = std::move(corrections);
  corrections_.serving(map_.epoch());
  restartConsistency();
  integrations_ = metadata->journal_sequence;
  if (replay_guard_ != nullptr) replay_guard_->importCounters(metadata->auth_counters);
}

std::int64_t MapService::replayJournal(const JournalContents& contents, bool show_progress) {
  if (contents.base_sequence > integrations_)
    throw std::runtime_error("journal continues a snapshot at sequence " +
                             std::to_string(contents.base_sequence) + " but the state is at " +
                             std::to_string(integrations_) +
                             ": restore the matching snapshot (--restore)");
  ProgressBar progress("replaying journal", contents.requests.size(), show_progress);
  std::int64_t applied = 0;
  std::int64_t sequence = contents.base_sequence;
  for (const auto& bytes : contents.requests) {
    ++sequence;
    progress.tick();
    if (sequence <= integrations_) continue;  // already in the snapshot
    // Entries of a pre-gravity server decode too (without a gravity reference).
    const auto request = decodeJournalEntry(bytes.data(), bytes.size());
    if (!request)
      throw std::runtime_error("journal entry " + std::to_string(sequence) + " does not decode");
    integrate_reply_t reply{};
    if (Status s = applyIntegrate(*request, reply, false); !s.ok())
      throw std::runtime_error("journal entry " + std::to_string(sequence) +
                               " was not applied: " + s.message);
    applied += reply.duplicate ? 0 : 1;
  }
  progress.finish();
  return applied;
}

void MapService::openDurability(const Durability& durability,
                                const std::optional<std::filesystem::path>& restore_snapshot) {
  if (durability.journal_file && !durability.snapshot_file)
    throw std::runtime_error("a journal needs a snapshot file to checkpoint into");
  durability_ = Durability{};  // no consistency store is touched before it is read
  if (restore_snapshot) loadSnapshot(*restore_snapshot);
  durability_ = durability;
  // The consistency store beside the snapshot file goes with that file only.
  std::error_code ec;
  if (restore_snapshot && durability.snapshot_file &&
      std::filesystem::weakly_canonical(*restore_snapshot, ec) ==
          std::filesystem::weakly_canonical(*durability.snapshot_file, ec))
    resumeConsistency();
  else
    restartConsistency();
  if (durability.journal_file && std::filesystem::exists(*durability.journal_file))
    replayJournal(Journal::read(*durability.journal_file), durability.show_progress);
  if (durability_.journal_file) {
    // Checkpoint right away: the snapshot now holds the replayed state and the journal starts
    // clean (also dropping a torn last event left by the crash).
    if (consistency_) consistency_->checkpoint(integrations_, map_.version());
    saveSnapshot(*durability_.snapshot_file);
    journal_ = std::make_unique<Journal>(*durability_.journal_file, integrations_,
                                         durability_.journal_sync);
  }
}

std::int64_t MapService::checkpoint() {
  if (!durability_.snapshot_file) return 0;
  // The consistency store's mark first: a snapshot on disk always has one.
  if (consistency_) consistency_->checkpoint(integrations_, map_.version());
  saveSnapshot(*durability_.snapshot_file);
  // Only after the snapshot is safely renamed into place may the journal forget its entries.
  if (journal_) journal_->restart(integrations_);
  return map_.stats().num_voxels;
}

bool MapService::acksWaitForSync() const {
  return journal_ && journal_->syncMode() == JournalSync::kBatch;
}

void MapService::syncJournal() {
  if (journal_) journal_->sync();
}

}  // namespace socc::service
