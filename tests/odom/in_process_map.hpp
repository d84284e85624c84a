#pragma once
// Relocalization's MapAccess over an in-process grid: what map_server answers to LOCALIZE
// (GlobalLocalizer) and GET_CHUNK, without LCM. For the relocalization tests and benchmark.
#include <algorithm>
#include <chrono>
#include <ctime>
#include <optional>
#include <vector>

#include "closed_loop_harness.hpp"
#include "global_localizer.hpp"
#include "socc/odom/relocalization.hpp"

namespace socc::odom::harness {

/// The server's search on the tests' small socc-sim maps (about 40 frames): a third of the
/// default draw budget finds the place, and the tests check the client's rules, not the search's
/// recall (bench_relocalization measures that with the defaults, as does the KITTI test).
inline socc::localization::LocalizerParams smallMapSearch() {
  socc::localization::LocalizerParams p;
  p.search.max_iterations = 10'000;
  return p;
}

class InProcessMap : public MapAccess {
 public:
  static constexpr int kDiagnosed = 32;

  InProcessMap(const socc::map::SemanticOccupancyMap& map, const OdomConfig& cfg,
               const socc::localization::LocalizerParams& params = {})
      : map_(map), cfg_(cfg), localizer_(params) {}

  std::vector<Eigen::Isometry3d> candidates(const std::vector<Eigen::Vector3f>& scan,
                                            const std::optional<PoseHint>& hint, int max) override {
    std::optional<socc::localization::LocalizeHint> h;
    if (hint)
      h = socc::localization::LocalizeHint{hint->position, hint->yaw, hint->radius,
                                           hint->yaw_tolerance};
    const auto start = std::chrono::steady_clock::now();
    const std::clock_t cpu_start = std::clock();
    // All kept hypotheses (the ranking does not depend on how many are asked for), so that a
    // diagnosis sees the true place's rank beyond the max returned.
    last_ = localizer_.localize(map_, scan, h, std::max(max, kDiagnosed));
    server_seconds_ =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    server_cpu_seconds_ = static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC;
    std::vector<Eigen::Isometry3d> out;
    for (const auto& c : last_.candidates)
      if (static_cast<int>(out.size()) < max) out.push_back(c.pose);
    return out;
  }
  LocalMap chunk(const Eigen::Vector3d& center) override { return chunkAround(map_, center, cfg_); }
  std::vector<SpaceCheck> check(const std::vector<Eigen::Vector3f>& scan,
                                const std::vector<Eigen::Isometry3d>& poses) override {
    std::vector<SpaceCheck> out;
    for (const Eigen::Isometry3d& pose : poses) {
      const auto c = socc::localization::checkFreeSpace(map_, scan, pose);
      out.push_back({c.observed, c.free});
    }
    return out;
  }

  /// Server time of the last candidates() call (descriptor upkeep included) [s].
  double serverSeconds() const { return server_seconds_; }
  /// CPU time of the last candidates() call, all threads [s]: what it costs whatever the load.
  double serverCpuSeconds() const { return server_cpu_seconds_; }
  std::size_t mapKeypoints() const { return localizer_.mapKeypoints(); }
  /// The search's answer to the last candidates() call (scores of the candidates), with up to
  /// kDiagnosed candidates of which the first max were returned.
  const socc::localization::LocalizeAnswer& lastAnswer() const { return last_; }
  const socc::map::SemanticOccupancyMap& map() const { return map_; }

 private:
  const socc::map::SemanticOccupancyMap& map_;
  OdomConfig cfg_;
  socc::localization::GlobalLocalizer localizer_;
  double server_seconds_ = 0.0;
  double server_cpu_seconds_ = 0.0;
  socc::localization::LocalizeAnswer last_;
};

}  // namespace socc::odom::harness
