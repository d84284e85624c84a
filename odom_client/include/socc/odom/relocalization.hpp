#pragma once
// Finding the robot in the shared map without a pose (odom_client --relocalize, recovery after
// LOST, --resume after an outage; docs/relocalization.md). The server proposes candidate poses
// for the scan (LOCALIZE: FPFH + RANSAC over its whole map); each is verified here by SOCC-ICP
// against the map around it. A pose is accepted only when its registration is healthy, it puts
// at most relocalize_max_free of its points where the map's rays passed freely (the server's
// free-space check: a scan seen from the wrong place sees through the map's walls), and its
// evidence (the share it explains minus the share it puts into free space) is at least
// relocalize_min_fitness (relocalize(): the share explained alone) and exceeds any other such
// place's by relocalize_margin: a place that only looks like another is left unlocalized rather
// than guessed, and the caller tries the next scan.
#include <Eigen/Geometry>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "socc/odom/local_map.hpp"
#include "socc/odom/odom_config.hpp"
#include "socc/odom/odometry.hpp"

namespace socc::odom {

/// Narrows the search: candidates within radius of position (map frame), heading within
/// yaw_tolerance of yaw.
struct PoseHint {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  double yaw = 0.0;             // [rad]
  double radius = 0.0;          // [m]
  double yaw_tolerance = M_PI;  // [rad]; pi: any heading
};

/// Where a scan's points land in the map at a pose (LOCALIZE check mode).
struct SpaceCheck {
  double observed = 0.0;  // share of the points in voxels the map observed
  double free = 0.0;      // of those, the share in voxels the map holds free
};

/// What a MapAccess throws when the map service cannot answer now (its searches all taken, or the
/// map replaced while the search ran, after MapClient's resends; for a robot in its own frame
/// also no reply from a server that answered it before: ServiceMapAccess's NoReply): nothing
/// was learnt, and the same search may be asked again later.
class MapBusy : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// What relocalization needs of the map service (MapClient over LCM, or an in-process map).
class MapAccess {
 public:
  virtual ~MapAccess() = default;
  /// Up to max candidate poses (map_T_sensor) of scan (sensor frame), best first.
  virtual std::vector<Eigen::Isometry3d> candidates(const std::vector<Eigen::Vector3f>& scan,
                                                    const std::optional<PoseHint>& hint,
                                                    int max) = 0;
  /// The registration target around center.
  virtual LocalMap chunk(const Eigen::Vector3d& center) = 0;
  /// The free-space check of scan at each pose.
  virtual std::vector<SpaceCheck> check(const std::vector<Eigen::Vector3f>& scan,
                                        const std::vector<Eigen::Isometry3d>& poses) = 0;
};

/// Why a relocalization gave no pose (Relocalization::refusal; problem says it in words).
enum class Refusal {
  kNone,            // a pose, or not judged
  kNoCandidate,     // the scan matches nothing in the map
  kNoRegistration,  // no candidate pose survived registration
  kFreeSpace,       // every registered place puts the scan into space the map saw free
  kLowFitness,      // the best place explains too little of the scan
  kAmbiguous,       // two places explain it about as well
};
inline constexpr int kRefusalKinds = 6;

/// Its name in reports and stats ("no_candidate", ..., "ambiguous"; "none").
const char* refusalName(Refusal refusal);

struct Relocalization {
  std::optional<Eigen::Isometry3d> pose;  // accepted: map_T_sensor at the scan's reference time
  std::string problem;                    // why not, when not
  Refusal refusal = Refusal::kNone;       // the same as a kind, from relocalize() (a
                                          // Relocalizer's verdict says it in problem only)
  int candidates = 0;                     // proposed by the server
  double fitness = 0.0;                   // of the best verified candidate
  double free = 0.0;                      // free-space share of the best verified candidate
  double evidence = 0.0;                  // fitness - free of the best verified candidate
  double runner_up = 0.0;                 // evidence of the next distinct verified candidate
  int confirmed = 0;                      // consecutive scans the best place has led (Relocalizer)
  double lead = 0.0;           // its evidence above the runner-up's, summed over them (Relocalizer)
  int stacked = 1;             // scans accumulated by odometry into the matched cloud (Relocalizer)
  std::int64_t map_epoch = 0;  // the map instance pose is in (integrate_request_t::map_epoch)
};

/// A candidate pose refined by registration and judged against the map.
struct VerifiedPlace {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // refined map_T_sensor
  double fitness = 0.0;  // share of the scan within 0.5 m of the map
  double free = 0.0;     // share of the scan in the map's free space (weighed by its evidence)
  std::int64_t map_epoch = 0;  // the map instance pose is in (LocalMap::epoch of its chunk)
  // What the place explains net of what it contradicts: the scan's points a place puts into
  // space the map saw free are evidence against it, as those near the map are for it.
  double evidence() const { return fitness - free; }
};

/// Poses closer than 1 m / 5 deg are one place (registrations from two candidates converged).
bool samePlace(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b);

/// Each of poses registered by SOCC-ICP against the map around it (healthy only, one per place)
/// and checked against the map's free space (at most relocalize_max_free): the places consistent
/// with the map, best evidence first. points: the scan as sent to LOCALIZE (localizationPoints).
/// problem (and refusal, when given): why none is, when none is.
std::vector<VerifiedPlace> verifyPlaces(const OdomConfig& config, const PreparedScan& scan,
                                        const std::vector<Eigen::Vector3f>& points, MapAccess& map,
                                        const std::vector<Eigen::Isometry3d>& poses,
                                        std::string& problem, Refusal* refusal = nullptr);

/// Percent text of a share, as the verdicts print it ("42 %").
std::string percentText(double share);

/// One attempt on one scan, accepted at once (no confirmation by later scans; the server's
/// loop-closure and odometry-edge checks). Its relocalize_min_fitness holds the share explained
/// alone, not net of the free share as a searching robot's (PlaceTracker): against a submap of
/// a few keyframe scans, whose free voxels were each crossed by few rays, the net share refused
/// the scan-to-scan edge that corrects a snap (OdometryEdge.ASnapAtTheRevisit...), and the
/// closures were measured with 0 wrong on it. A robot searching its pose uses Relocalizer.
Relocalization relocalize(const OdomConfig& config, const PreparedScan& scan, MapAccess& map,
                          const std::optional<PoseHint>& hint);

/// The server's LOCALIZE request limit (map_server limits.max_localize_points default).
inline constexpr std::size_t kMaxLocalizePoints = 100'000;

/// The scan as sent to LOCALIZE: voxel-downsampled to relocalize_voxel_size, at most max_points.
std::vector<Eigen::Vector3f> localizationPoints(const LabeledCloud& cloud, double voxel_size,
                                                std::size_t max_points);

}  // namespace socc::odom
