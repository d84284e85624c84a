#pragma once
// Relocalization's view of the map service over LCM: LOCALIZE for candidates, GET_CHUNK for the
// registration target around each.
#include "socc/odom/odom_config.hpp"
#include "socc/odom/relocalization.hpp"
#include "socc/rpc/map_client.hpp"

namespace socc::odom {

/// What a map service that gave no reply (after MapClient's retries) means to a search: the end
/// of the run (a robot that needs the service to go on, or a server that never answered), or
/// only of that search (MapBusy: an own-frame robot, which maps without the service and writes
/// nothing to it before its merge, searching a server that answered it before).
enum class NoReply { kFails, kBusy };

class ServiceMapAccess : public MapAccess {
 public:
  ServiceMapAccess(rpc::MapClient& client, const OdomConfig& config,
                   NoReply no_reply = NoReply::kFails)
      : client_(client), config_(config), no_reply_(no_reply) {}
  /// Throw MapBusy when the service cannot answer now (costsOnlyTheSearch), std::runtime_error
  /// when it fails otherwise (after MapClient's retries).
  std::vector<Eigen::Isometry3d> candidates(const std::vector<Eigen::Vector3f>& scan,
                                            const std::optional<PoseHint>& hint, int max) override;
  LocalMap chunk(const Eigen::Vector3d& center) override;
  std::vector<SpaceCheck> check(const std::vector<Eigen::Vector3f>& scan,
                                const std::vector<Eigen::Isometry3d>& poses) override;

 private:
  rpc::MapClient& client_;
  const OdomConfig& config_;
  NoReply no_reply_;
};

/// Whether a failed call of a search ends only that search: the server's refusal while all its
/// searches are taken (or the map was replaced during the search; rpc::kSearchesBusy), or no
/// reply at all when no_reply is kBusy.
bool costsOnlyTheSearch(const rpc::CallError& e, NoReply no_reply);

/// "LOCALIZE failed after 2 attempt(s): ... (STATUS)": the one wording of a failed call.
std::string callError(const char* what, const rpc::CallError& e, int attempts);

}  // namespace socc::odom
