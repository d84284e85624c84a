// The consistency service's store beside the map's snapshot (docs/consistency.md,
// "Durability"): started anew with each new grid, resumed after a restart when it covers the
// snapshot the map was restored from.
#include <iostream>

#include "consistency_restore.hpp"
#include "map_service.hpp"

namespace socc::service {

std::optional<std::filesystem::path> MapService::consistencyStoreFile() const {
  if (!config_.consistency.enabled || !durability_.snapshot_file) return std::nullopt;
  return durability_.snapshot_file->string() + ".consistency";
}

std::unique_ptr<consistency::KeyframeStore> MapService::newConsistencyStore(
    bool foreign_base) const {
  const auto file = consistencyStoreFile();
  if (!file) return nullptr;
  try {
    return consistency::KeyframeStore::create(*file, foreign_base,
                                              durability_.journal_sync != JournalSync::kNone);
  } catch (const std::exception& e) {
    std::cerr << "map_server: warning: " << e.what()
              << ": the consistency state is not kept (a restart will not rebuild the grid)\n";
    return nullptr;
  }
}

void MapService::resumeConsistency() {
  const auto file = consistencyStoreFile();
  if (!file) return restartConsistency();
  std::string why = "it does not exist";
  try {
    if (!std::filesystem::exists(*file)) throw std::runtime_error(why);
    const consistency::StoreContents contents = consistency::KeyframeStore::read(*file);
    if (!contents.problem.empty()) std::cerr << "map_server: " << contents.problem << '\n';
    if (const auto* mark =
            consistency::coveringMark(contents, integrations_, map_.version(), why)) {
      consistency::ConsistencyParams params = config_.consistency;
      params.correct_grid = params.correct_grid && !contents.foreign_base;
      consistency_foreign_ = contents.foreign_base;
      consistency_.reset();
      consistency_ = std::make_unique<consistency::ConsistencyService>(
          params, config_.map, odom::OdomConfig{},
          consistency::KeyframeStore::resume(*file, contents,
                                             durability_.journal_sync != JournalSync::kNone),
          &contents, mark->grid_serial);
      std::cerr << "map_server: consistency state restored: " << contents.keyframes.size()
                << " keyframes (and " << consistency::waitingKeyframes(contents).size()
                << " waiting for the worker), " << contents.closures.size() << " closures ("
                << file->string() << ")\n";
      return;
    }
  } catch (const std::exception& e) {
    why = e.what();
    std::error_code ec;  // kept for inspection, not replaced by the new store
    std::filesystem::rename(*file, file->string() + ".unreadable", ec);
  }
  std::cerr << "map_server: consistency state not restored from " << file->string() << ": " << why
            << "; the service starts empty"
            << (map_.stats().num_voxels != 0 ? " and does not rebuild this grid\n" : "\n");
  restartConsistency();
}

}  // namespace socc::service
