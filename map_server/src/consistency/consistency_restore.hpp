#pragma once
// Whether a consistency store can restore the service for a map restored from a snapshot
// (docs/consistency.md, "Durability"). The service's own side (writing records, starting from
// them) is in consistency_restore.cpp.
#include <cstdint>
#include <string>
#include <vector>

#include "keyframe_store.hpp"

namespace socc::consistency {

/// The mark of the snapshot at (journal_sequence, map_version) when contents hold every
/// keyframe that snapshot's integrations made and the rebuild its grid is; else null, with
/// the reason in problem.
/// The waiting keyframes of contents that no keyframe record holds (the worker had not
/// processed them when the writer stopped), each once, in the order they were observed.
std::vector<const StoredWaiting*> waitingKeyframes(const StoreContents& contents);

const StoredCheckpoint* coveringMark(const StoreContents& contents, std::int64_t journal_sequence,
                                     std::int64_t map_version, std::string& problem);

}  // namespace socc::consistency
