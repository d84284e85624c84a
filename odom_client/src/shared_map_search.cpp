#include "socc/odom/shared_map_search.hpp"

#include <chrono>
#include <stdexcept>
#include <utility>

#include "socc/odom/service_map_access.hpp"

namespace socc::odom {

SharedMapSearch::SharedMapSearch(const OdomConfig& config, rpc::MapClient& client)
    : config_(config), client_(client), relocalizer_(config) {}

SharedMapSearch::~SharedMapSearch() {
  if (running_.valid()) running_.wait();
}

void SharedMapSearch::start(PreparedScan stacked, int scans, const Eigen::Isometry3d& motion,
                            std::optional<PoseHint> hint, std::int64_t seq,
                            const Eigen::Isometry3d& own_pose) {
  if (running()) throw std::logic_error("SharedMapSearch: a search is running");
  running_ = std::async(std::launch::async, [this, stacked = std::move(stacked), scans, motion,
                                             hint = std::move(hint), seq, own_pose] {
    // This robot maps without the service: when the server answered it before, a search that
    // got no reply (a loaded server) is a search without a place; a server that never answered
    // may not be running at all, and the run ends with the error as before.
    ServiceMapAccess map(client_, config_, client_.answered() ? NoReply::kBusy : NoReply::kFails);
    SearchOutcome outcome;
    outcome.found = relocalizer_.addStacked(stacked, scans, motion, map, hint);
    outcome.seq = seq;
    outcome.own_pose = own_pose;
    return outcome;
  });
}

std::optional<SearchOutcome> SharedMapSearch::poll() {
  if (!running_.valid() || running_.wait_for(std::chrono::seconds(0)) != std::future_status::ready)
    return std::nullopt;
  return running_.get();
}

std::optional<SearchOutcome> SharedMapSearch::wait() {
  if (!running_.valid()) return std::nullopt;
  return running_.get();
}

}  // namespace socc::odom
