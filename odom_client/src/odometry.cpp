#include "socc/odom/odometry.hpp"

#include <cmath>
#include <stdexcept>

#include "socc/labels.hpp"
#include "socc/odom/deskew.hpp"
#include "socc/odom/point_times.hpp"
#include "socc/odom/preprocessing.hpp"
#include "socc/odom/scan_map.hpp"
#include "socc/odom/scan_normals.hpp"

namespace socc::odom {
namespace {

// A deskew pass whose twist changed less than this over one sweep changes the scan by less than
// the noise of a LiDAR point: further passes would not move the estimate.
constexpr double kSettledTranslation = 0.002;  // [m per sweep]
constexpr double kSettledRotation = 2e-4;      // [rad per sweep]
// Voxel size of the held first scan's own map in the start-up registration (the map server's
// default resolution).
constexpr double kStartupVoxelSize = 0.5;

bool settled(const Vector6d& change, double sweep) {
  return change.head<3>().norm() * sweep < kSettledTranslation &&
         change.tail<3>().norm() * sweep < kSettledRotation;
}

// map plus the voxels of cloud (map frame).
LocalMap withCloud(const LocalMap& map, const LabeledCloud& cloud) {
  const LocalMap own = buildScanMap(cloud, kStartupVoxelSize);
  std::vector<MapVoxel> voxels;
  voxels.reserve(map.size() + own.size());
  for (std::size_t i = 0; i < map.size(); ++i) voxels.push_back(map.voxel(i));
  for (std::size_t i = 0; i < own.size(); ++i) voxels.push_back(own.voxel(i));
  return LocalMap(std::move(voxels));
}

// First-motion search: a hypothesis this close (twist norm: metres and radians) to where an
// earlier one ended is in the same basin.
constexpr double kSameBasin = 0.02;

// First-motion search: its hypotheses are registered on this multiple of v_adapt (a ninth of the
// points on surfaces): 2x halved the search on frame 1 of KITTI 00, 3x halved it again; the
// robustness matrix and the KITTI sweep give the same errors with either (docs/robustness.md).
constexpr double kSearchGrid = 3.0;

// A point this close to the map is explained by it: the map's resolution.
constexpr double kNearMap = 0.5;  // [m]

// A scan this many frame periods after the last one follows a gap (dropped scans, a pause).
constexpr double kGapPeriods = 1.5;

// A retry's fit at the wide threshold is loose evidence (with a 2 m kernel a scan of another
// place fits somewhere at half its RMS: a kidnapped robot's foreign scan did): one that also
// contradicts the motion model is not trusted. Healthy retries (a prediction a little off, or a
// threshold below the sensor's noise) move as the model expects.
FrameEstimate judgedRetry(FrameEstimate retry) {
  retry.retried = true;
  if (retry.health.healthy() && !retry.health.surprise.empty())
    retry.health.problem = "wide retry and " + retry.health.surprise;
  return retry;
}

}  // namespace

struct Odometry::Sweep {
  RegistrationResult registration;
  LabeledCloud cloud;                  // the deskewed, downsampled points registered
  std::optional<ScanNormals> normals;  // of its points (sparse_pairs_along_scan_normal)
  std::size_t points() const { return cloud.size(); }
};

Odometry::Odometry(const OdomConfig& config, const Eigen::Isometry3d& initial_pose,
                   bool initial_pose_known)
    : config_(config),
      class_factor_(classFactors(config)),
      params_{config.planarity_threshold,
              config.gamma,
              config.w_lower,
              config.max_iterations,
              config.convergence,
              config.point_to_plane,
              config.sparse_voxel_pairs,
              config.sparse_point_pairs,
              {},
              0.0},
      threshold_(config.initial_threshold, config.min_motion, config.max_range),
      voxel_size_(config.initial_voxel_size, config.min_voxel_size, config.max_voxel_size,
                  config.target_points),
      period_(config.frame_period),
      pose_(initial_pose),
      keep_first_pose_(initial_pose_known && !config.refine_initial_pose),
      tilt_(config.gravity_tilt_walk_deg * M_PI / 180.0) {
  if (!config.range_calibration) return;
  RangeCalibrationParams calibration;
  calibration.planarity_threshold = config.planarity_threshold;
  range_calibration_.emplace(calibration);
}

PreparedScan prepareScan(const OdomConfig& config, const LabeledCloud& raw, std::int64_t seq,
                         std::int64_t utime) {
  if (const std::string problem = checkCloud(raw); !problem.empty())
    throw std::invalid_argument("bad scan: " + problem);
  PreparedScan out;
  out.seq = seq;
  out.utime = utime;
  out.cloud = rangeFilter(raw, config.min_range, config.max_range);
  correctElevation(out.cloud, config.vertical_angle_correction_deg * M_PI / 180.0);
  if (!config.use_semantics) dropLabels(out.cloud);
  if (!config.deskew)
    out.cloud.times.clear();
  else if (!out.cloud.hasTimes() && config.azimuth_times)
    out.cloud.times =
        azimuthTimes(out.cloud.points, {config.frame_period, config.azimuth_start_deg,
                                        config.azimuth_clockwise, config.scan_time_in_sweep});
  out.mid_time = sweepMidTime(out.cloud);
  return out;
}

PreparedScan Odometry::prepare(const LabeledCloud& raw, std::int64_t seq,
                               std::int64_t utime) const {
  return prepareScan(config_, raw, seq, utime);
}

Eigen::Isometry3d Odometry::predictedPose(const PreparedScan& scan) const {
  if (time_ < 0.0) return pose_;
  return pose_ * expSe3(twist_ * (scan.time() - time_));
}

Eigen::Vector3d Odometry::predictedPosition(double seconds) const {
  return (pose_ * expSe3(twist_ * seconds)).translation();
}

Vector6d Odometry::twistTo(const Eigen::Isometry3d& mid_pose, double time) const {
  return logSe3(pose_.inverse() * mid_pose) / (time - time_);
}

FrameEstimate Odometry::registerFrame(const PreparedScan& scan, const LocalMap& map) {
  if (!range_calibration_) return registerCorrected(scan, map);
  std::optional<PreparedScan> corrected;  // a copy only once the lasers are fitted
  if (range_calibration_->corrects()) {
    corrected = scan;
    range_calibration_->apply(corrected->cloud);
  }
  const PreparedScan& used = corrected ? *corrected : scan;
  FrameEstimate out = registerCorrected(used, map);
  if (out.registered && out.health.healthy() && !out.held)
    range_calibration_->observe(used.cloud.points, out.cloud.points, out.pose, map);
  return out;
}

FrameEstimate Odometry::registerCorrected(const PreparedScan& scan, const LocalMap& map) {
  if (!has_motion_model_ && !held_ && scan.cloud.hasTimes()) {
    held_ = scan;  // deskewed once the next scan gives the motion
    FrameEstimate out;
    out.seq = scan.seq;
    out.utime = scan.utime;
    out.gravity = scan.gravity;
    out.pose = pose_;
    out.held = true;
    return out;
  }
  if (held_) return bootstrap(scan, map);
  const bool keep = keep_first_pose_ && !has_motion_model_;
  const Eigen::Isometry3d prediction = predictedPose(scan);
  if (keep || !registrable(map)) return unregistered(scan, prediction);

  FrameEstimate out = estimateWithRetries(scan, map);
  if (out.health.healthy() && !out.health.surprise.empty() && surprise_check_)
    out.health.problem = surprise_check_(out);
  if (!out.health.healthy()) {
    // Not trusted: the state follows the prediction (the estimate stays for the log).
    FrameEstimate kept = unregistered(scan, prediction);
    kept.registration = out.registration;
    kept.health = out.health;
    kept.retried = out.retried;
    return kept;
  }
  const Eigen::Isometry3d mid = out.registration.pose;
  // The threshold follows the model's error over one period; after a gap its error is larger
  // by what the gap, not the model, did.
  const bool on_time = time_ >= 0.0 && period_.periods(scan.time() - time_) < kGapPeriods;
  if (has_motion_model_ && on_time) threshold_.update(prediction.inverse() * mid);
  advance(scan, out, mid);
  if (const std::optional<Eigen::Vector3d> up = upAtMid(scan, twist_))
    tilt_.update(mid.linear(), *up, scan.gravity->sigma, scan.time());
  return out;
}

std::optional<Eigen::Vector3d> Odometry::upAtMid(const PreparedScan& scan,
                                                 const Vector6d& twist) const {
  if (!scan.gravity || !(scan.gravity->sigma > 0.0)) return std::nullopt;
  // map_R_mid * x = map_R_scan * g with map_R_scan = map_R_mid * Exp(-mid_time * omega).
  return Eigen::Vector3d(expSe3(-scan.mid_time * twist).linear() * scan.gravity->up);
}

FrameEstimate Odometry::estimateWithRetries(const PreparedScan& scan, const LocalMap& map) {
  // After a gap (dropped scans, a paused recording) the prediction spans several periods: its
  // error grows with them, and so does the threshold that has to catch it.
  const double periods = time_ >= 0.0 ? period_.periods(scan.time() - time_) : 1.0;
  const double sigma = threshold_.sigma();
  const double wide = std::max(2.0 * sigma, config_.initial_threshold);
  FrameEstimate out = estimate(scan, map, std::min(sigma * periods, wide), twist_);
  if (out.health.healthy()) return out;
  // A wider threshold from the constant-velocity prediction catches a motion the model missed.
  const FrameEstimate retry = judgedRetry(estimate(scan, map, wide, twist_));
  if (retry.health.healthy() || periods < kGapPeriods) return retry.health.healthy() ? retry : out;
  // A pause: the robot may have stood still while the recording did.
  const FrameEstimate still = judgedRetry(estimate(scan, map, wide, Vector6d::Zero()));
  return still.health.healthy() ? still : out;
}

bool Odometry::registrable(const LocalMap& map) const {
  return map.size() >= static_cast<std::size_t>(std::max(config_.min_map_points, 1));
}

FrameEstimate Odometry::estimate(const PreparedScan& scan, const LocalMap& map, double sigma,
                                 const Vector6d& model_twist) {
  RegistrationParams params = params_;
  if (const std::optional<Eigen::Vector3d> up = upAtMid(scan, model_twist))
    params.tilt = tilt_.prior(*up, scan.gravity->sigma, scan.time());
  FrameEstimate out = estimateWith(scan, map, sigma, model_twist, params);
  // Along a degenerate registration's weakest direction the scan's evidence is a few pairs' worth:
  // the sensor's noise and its calibration errors, a texture that moves with the sensor, pull
  // the pose where they like, and the motion model follows them (a featureless corridor
  // accelerated to 4 m/s in five frames and the robot was declared lost). There the
  // constant-velocity prediction enters as evidence worth min_constraint planar pairs, the
  // least a direction needs not to be degenerate: with a few pairs the odometry coasts on the
  // prediction, with 30 (a sparse sensor in a turn) the scan still moves it about half way.
  const bool predicted = time_ >= 0.0 && scan.time() > time_ && twist_known_;
  if (!out.health.degenerate || !predicted || !config_.hold_degenerate_direction) return out;
  RegistrationParams hold = params;
  hold.hold_direction = out.health.weakest_direction;
  hold.hold_position = (pose_ * expSe3(model_twist * (scan.time() - time_))).translation();
  hold.hold_pairs = config_.min_constraint;
  return estimateWith(scan, map, sigma, model_twist, hold);
}

FrameEstimate Odometry::estimateWith(const PreparedScan& scan, const LocalMap& map, double sigma,
                                     const Vector6d& model_twist,
                                     const RegistrationParams& params) {
  FrameEstimate out;
  out.sigma = sigma;
  Eigen::Isometry3d mid = time_ < 0.0 ? pose_ : pose_ * expSe3(model_twist * (scan.time() - time_));
  Vector6d twist = model_twist;
  const bool anchored = time_ >= 0.0 && scan.time() > time_;
  if (anchored && !twist_known_) {
    mid = searchFirstMotion(scan, map, pose_, scan.time() - time_, sigma);
    twist = twistTo(mid, scan.time());
  }
  for (int pass = 0; pass < config_.deskew_iterations; ++pass) {
    // The twist measured from the last pose to this one is the prior of the sweep's own.
    const Vector6d measured = twistTo(mid, scan.time());
    std::optional<SweepTwistPrior> prior;
    if (anchored && scan.cloud.hasTimes()) prior = sweepPrior(twist, measured);
    const Sweep s = registerSweep(scan, map, mid, twist, sigma, prior ? &*prior : nullptr, &params);
    out.registration = s.registration;
    out.registered_points = s.points();
    out.deskew_passes = pass + 1;
    mid = s.registration.pose;
    if (!anchored || !scan.cloud.hasTimes()) break;
    const Vector6d measured_after = twistTo(mid, scan.time());
    const Vector6d next =
        prior ? Vector6d(twist + s.registration.twist_correction) : measured_after;
    // The prior held the twist near the motion to the pose before this pass. Where the pass moved
    // the pose, that motion moved with it and the next pass's twist may too: in a turn that slows
    // down, stopping here left each sweep deskewed with the last one's turn rate (indoor zigzags
    // with a VLP-16: 0.7 deg of heading per turn; docs/robustness.md "Short paths on three seeds").
    const bool moved = prior && !settled(measured_after - measured, config_.frame_period);
    const bool done = settled(next - twist, config_.frame_period) && !moved;
    twist = next;
    if (done) break;
  }
  out.voxel_size = voxel_size_.size();  // as the passes used it (the first may have adapted it)
  finish(scan, mid, twist, out);
  out.registered = true;
  judge(scan, out);
  return out;
}

std::optional<SweepTwistPrior> Odometry::sweepPrior(const Vector6d& deskew_twist,
                                                    const Vector6d& measured) const {
  if (config_.sweep_twist_sigma_linear <= 0.0 && config_.sweep_twist_sigma_angular <= 0.0)
    return std::nullopt;
  SweepTwistPrior prior;
  prior.offset = deskew_twist - measured;
  prior.sigma << Eigen::Vector3d::Constant(config_.sweep_twist_sigma_linear),
      Eigen::Vector3d::Constant(config_.sweep_twist_sigma_angular);
  return prior;
}

Odometry::Sweep Odometry::registerSweep(const PreparedScan& scan, const LocalMap& map,
                                        const Eigen::Isometry3d& guess, const Vector6d& twist,
                                        double sigma, const SweepTwistPrior* prior,
                                        const RegistrationParams* given) {
  const RegistrationParams& params = given ? *given : params_;
  Sweep out;
  const SweepMotion motion(scan.cloud, twist, scan.mid_time);
  out.cloud = downsample(scan.cloud, &motion);
  LabeledCloud& down = out.cloud;
  for (float& t : down.times) t -= static_cast<float>(scan.mid_time);  // the pose's instant
  // Neighbourhoods of a few downsampling cells span two or more rings of a sparse sensor.
  if (config_.sparse_pairs_along_scan_normal) {
    std::vector<std::uint8_t> on_ground(down.labels.size());  // none without labels
    for (std::size_t i = 0; i < on_ground.size(); ++i) on_ground[i] = isGround(down.labels[i]);
    out.normals.emplace(down.points, 3.0 * voxel_size_.size(), config_.planarity_threshold,
                        std::move(on_ground));
  }
  const ScanNormals* normals = out.normals ? &*out.normals : nullptr;
  // The initial threshold is wide so that it catches an unknown motion (or a rough initial pose
  // in a map other robots built): its kernel also gives weight to wrong correspondences, which
  // leaves the pose biased by centimetres. Halving sigma from the coarse result removes them;
  // a pose that enters another robot's map this way would otherwise shift that map for everyone.
  // Only the last registration estimates the sweep's twist (the points stay deskewed with twist).
  const bool refine = !threshold_.calibrated() && config_.refine_threshold > 0.0;
  const auto last = [&](double s) { return !refine || s / 2.0 < config_.refine_threshold; };
  out.registration =
      registerScan(down, map, guess, sigma, params, last(sigma) ? prior : nullptr, normals);
  if (!refine) return out;
  for (double s = sigma / 2.0; s >= config_.refine_threshold; s /= 2.0) {
    const int iterations = out.registration.iterations;
    out.registration = registerScan(down, map, out.registration.pose, s, params,
                                    last(s) ? prior : nullptr, normals);
    out.registration.iterations += iterations;
  }
  return out;
}

FrameEstimate Odometry::registerAt(const PreparedScan& scan, const LocalMap& map,
                                   const Eigen::Isometry3d& guess) {
  FrameEstimate out;
  out.sigma = threshold_.sigma();
  const Sweep s = registerSweep(scan, map, guess, Vector6d::Zero(), out.sigma);
  out.registration = s.registration;
  out.registered_points = s.points();
  out.deskew_passes = 1;
  out.voxel_size = voxel_size_.size();
  finish(scan, s.registration.pose, Vector6d::Zero(), out);
  out.registered = registrable(map);
  out.health = judgeRegistration(out.registration, out.registered_points, out.sigma, config_);
  out.fitness = fractionNearMap(s.cloud.points, map, s.registration.pose, kNearMap);
  return out;
}

Eigen::Isometry3d Odometry::searchFirstMotion(const PreparedScan& scan, const LocalMap& map,
                                              const Eigen::Isometry3d& from, double dt,
                                              double sigma) {
  // The first motion of a run has no prior, and ICP started at "standing still" converges to
  // standing still on a straight street at speed: the along-track features are metres off and
  // get no kernel weight, while road and facades already fit. So speeds along the sensor's x axis
  // (the direction vehicles and most robots move in), 0.7 m per 10 Hz frame apart (well inside
  // the 2 m threshold's basin), are each registered coarsely, on a coarser grid (finding the
  // basin needs the scene's layout, not its detail); the pose that puts most points near the map
  // wins (ties: the first, slower one) and is refined by the caller on the registration grid.
  downsample(scan.cloud);  // settles v_adapt: every hypothesis is scored on the same grid
  // Finding the basin needs every constraint a young map offers, also the sparse voxels' pairs
  // along the scan's normals (biased by centimetres towards standing still, not by metres); the
  // refinement that follows drops them again when the configuration does (sparse_voxel_pairs).
  // Point pairs with sparse voxels stay as configured (sparse_point_pairs).
  RegistrationParams search = params_;
  search.sparse_voxel_pairs = true;
  // Without point times every hypothesis registers the same points: one whose iterations come
  // next to an earlier one's path would follow it into the basin it found (same score; ties go
  // to the earlier one anyway), so it stops there. With times each is deskewed with its own
  // speed and scored on its own.
  const bool same_points = !scan.cloud.hasTimes();
  if (same_points) search.join_distance = kSameBasin;
  std::optional<LabeledCloud> down;
  Eigen::Isometry3d best = from;
  double best_score = -1.0;
  for (const double speed : {0.0, 7.0, 14.0, 21.0, 28.0, 35.0, -7.0}) {
    if (std::abs(speed) > config_.max_linear_speed) continue;
    Vector6d twist = Vector6d::Zero();
    twist[0] = speed;
    if (!down || !same_points) {
      const SweepMotion motion(scan.cloud, twist, scan.mid_time);
      down = semanticVoxelDownsample(scan.cloud, kSearchGrid * voxel_size_.size(), class_factor_,
                                     &motion);
    }
    const RegistrationResult r = registerScan(*down, map, from * expSe3(twist * dt), sigma, search);
    // Each of its iterates leads into a basin explored now.
    search.join_path.insert(search.join_path.end(), r.path.begin(), r.path.end());
    if (r.joined) continue;
    search.join_path.push_back(r.pose);
    const double score = fractionNearMap(down->points, map, r.pose, kNearMap);
    if (score > best_score) {
      best_score = score;
      best = r.pose;
    }
  }
  return best;
}

LabeledCloud Odometry::downsample(const LabeledCloud& cloud, const SweepMotion* motion) {
  LabeledCloud down = semanticVoxelDownsample(cloud, voxel_size_.size(), class_factor_, motion);
  if (voxel_size_.farOff(down.size())) {
    // e.g. the first frame or a sudden change of scene: redo once with the corrected size.
    voxel_size_.update(down.size());
    down = semanticVoxelDownsample(cloud, voxel_size_.size(), class_factor_, motion);
  }
  return down;
}

FrameEstimate Odometry::bootstrap(const PreparedScan& scan, const LocalMap& map) {
  const PreparedScan first = std::move(*held_);
  held_.reset();
  const bool register_first = !keep_first_pose_ && registrable(map);
  const double sigma = threshold_.sigma();
  const double dt = scan.time() > first.time() ? scan.time() - first.time() : config_.frame_period;
  Vector6d twist = Vector6d::Zero();
  Eigen::Isometry3d mid0 = pose_, mid1 = pose_;
  FrameEstimate e0, e1;
  for (int pass = 0; pass < config_.deskew_iterations + 1; ++pass) {
    if (register_first)
      mid0 = registerSweep(first, map, mid0, twist, sigma).registration.pose;
    else  // the given (or initial) pose refers to the first scan's reference time
      mid0 = pose_ * expSe3((first.mid_time - config_.deskew_reference_time) * twist);
    const LocalMap target =
        withCloud(map, transformed(deskew(first.cloud, twist, first.mid_time), mid0));
    if (pass == 0) {
      mid1 = searchFirstMotion(scan, target, mid0, dt, sigma);
      twist = logSe3(mid0.inverse() * mid1) / dt;
    }
    const Sweep s = registerSweep(scan, target, mid1, twist, sigma);
    e1.registration = s.registration;
    e1.registered_points = s.points();
    e1.deskew_passes = pass + 1;
    mid1 = s.registration.pose;
    const Vector6d next = logSe3(mid0.inverse() * mid1) / dt;
    const bool done = settled(next - twist, config_.frame_period);
    twist = next;
    if (done) break;
  }
  e0.sigma = e1.sigma = sigma;
  e0.voxel_size = e1.voxel_size = voxel_size_.size();
  finish(first, mid0, twist, e0);
  finish(scan, mid1, twist, e1);
  e0.registered = register_first;
  e1.registered = true;
  e1.health = judgeRegistration(e1.registration, e1.registered_points, sigma, config_);
  judgeMotion(e1.health, twist, nullptr, dt, config_);
  e0.health = e1.health;  // the first scan is deskewed with this frame's motion
  released_ = std::move(e0);
  period_.add(dt);
  pose_ = mid1;
  time_ = scan.time();
  twist_ = twist;
  twist_known_ = true;
  has_motion_model_ = true;
  voxel_size_.update(e1.registered_points);
  return e1;
}

FrameEstimate Odometry::unregistered(const PreparedScan& scan, const Eigen::Isometry3d& mid_pose) {
  FrameEstimate out;
  out.sigma = threshold_.sigma();
  out.voxel_size = voxel_size_.size();
  out.registered_points = downsample(scan.cloud).size();  // keeps v_adapt following the scans
  finish(scan, mid_pose, twist_, out);
  advance(scan, out, mid_pose);
  return out;
}

void Odometry::finish(const PreparedScan& scan, const Eigen::Isometry3d& mid_pose,
                      const Vector6d& twist, FrameEstimate& out) const {
  const double ref = config_.deskew_reference_time;
  out.seq = scan.seq;
  out.utime = scan.utime;
  out.gravity = scan.gravity;
  out.pose = orthonormalized(mid_pose * expSe3((ref - scan.mid_time) * twist));
  out.cloud = deskew(scan.cloud, twist, ref);
  out.cloud.times.clear();  // deskewed: the points now all refer to the reference time
}

void Odometry::judge(const PreparedScan& scan, FrameEstimate& out) const {
  out.health = judgeRegistration(out.registration, out.registered_points, out.sigma, config_);
  if (time_ < 0.0 || !(scan.time() > time_)) return;
  judgeMotion(out.health, twistTo(out.registration.pose, scan.time()),
              twist_known_ ? &twist_ : nullptr, scan.time() - time_, config_);
}

void Odometry::advance(const PreparedScan& scan, const FrameEstimate& out,
                       const Eigen::Isometry3d& mid) {
  if (time_ >= 0.0 && scan.time() > time_ && out.registered) {
    twist_ = twistTo(mid, scan.time());
    twist_known_ = true;
  }
  if (time_ >= 0.0) period_.add(scan.time() - time_);
  pose_ = orthonormalized(mid);
  time_ = scan.time();
  has_motion_model_ = true;
  voxel_size_.update(out.registered_points);
}

std::optional<FrameEstimate> Odometry::takeReleasedFrame() {
  std::optional<FrameEstimate> out = std::move(released_);
  released_.reset();
  return out;
}

void Odometry::correct(const Eigen::Isometry3d& correction) {
  pose_ = correction * pose_;
  if (released_) released_->pose = correction * released_->pose;
}

void Odometry::moveFrame(const Eigen::Isometry3d& new_T_old) {
  correct(new_T_old);
  tilt_.moveFrame(new_T_old.linear());
}

void Odometry::reset(const Eigen::Isometry3d& pose) {
  pose_ = pose;
  time_ = -1.0;
  twist_.setZero();
  twist_known_ = false;
  has_motion_model_ = false;
  keep_first_pose_ = false;  // e.g. the last pose the server holds: the next scan is elsewhere
  held_.reset();
  released_.reset();
  threshold_.reset();
}

}  // namespace socc::odom
