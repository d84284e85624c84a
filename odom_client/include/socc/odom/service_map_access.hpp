#pragma once
// Relocalization's view of the map service over LCM: LOCALIZE for candidates, GET_CHUNK for the
// registration target around each.
#include "socc/odom/odom_config.hpp"
#include "socc/odom/relocalization.hpp"
#include "socc/rpc/map_client.hpp"

namespace socc::odom {

class ServiceMapAccess : public MapAccess {
 public:
  ServiceMapAccess(rpc::MapClient& client, const OdomConfig& config)
      : client_(client), config_(config) {}
  /// Throws std::runtime_error when the service fails (after MapClient's retries).
  std::vector<Eigen::Isometry3d> candidates(const std::vector<Eigen::Vector3f>& scan,
                                            const std::optional<PoseHint>& hint, int max) override;
  LocalMap chunk(const Eigen::Vector3d& center) override;
  std::vector<SpaceCheck> check(const std::vector<Eigen::Vector3f>& scan,
                                const std::vector<Eigen::Isometry3d>& poses) override;

 private:
  rpc::MapClient& client_;
  const OdomConfig& config_;
};

/// "LOCALIZE failed after 2 attempt(s): ... (STATUS)": the one wording of a failed call.
std::string callError(const char* what, const rpc::CallError& e, int attempts);

}  // namespace socc::odom
