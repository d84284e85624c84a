#pragma once
// Whether a consistency store can restore the service for a map restored from a snapshot
// (docs/consistency.md, "Durability"). The service's own side (writing records, starting from
// them) is in consistency_restore.cpp.
#include <cstdint>
#include <string>

#include "keyframe_store.hpp"

namespace socc::consistency {

/// The mark of the snapshot at (journal_sequence, map_version) when contents hold every
/// keyframe that snapshot's integrations made and the rebuild its grid is; else null, with
/// the reason in problem.
const StoredCheckpoint* coveringMark(const StoreContents& contents, std::int64_t journal_sequence,
                                     std::int64_t map_version, std::string& problem);

}  // namespace socc::consistency
