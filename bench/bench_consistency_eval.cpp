// bench_consistency_eval: scores what map_server --consistency-dir wrote (keyframes.txt,
// closures.txt, stats.txt) against the sequence's ground truth; one markdown row per figure and
// a last line that sums it up. Used by scripts/bench_consistency.sh (docs/consistency.md).
// Exit 1 when a target is missed: wrong closures > 0, map-frame ATE not --min-gain times lower
// than the odometry's, revisits mapped twice > --max-doubled.
#include <CLI/CLI.hpp>
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "consistency_output.hpp"
#include "socc/kitti_io.hpp"

namespace {

using socc::bench::ClosureRow;
using socc::bench::KeyframeRow;
using socc::bench::TiltFit;

std::map<std::string, double> readStats(const std::string& file) {
  std::ifstream in(file);
  std::map<std::string, double> stats;
  std::string key;
  double value = 0.0;
  while (in >> key >> value) stats[key] = value;
  return stats;
}

double angle(const Eigen::Isometry3d& t) {
  return Eigen::AngleAxisd(t.linear()).angle();
}

double rmse(const std::vector<double>& e) {
  double s = 0.0;
  for (const double v : e) s += v * v;
  return e.empty() ? 0.0 : std::sqrt(s / static_cast<double>(e.size()));
}

// With several robots, one row each: its keyframes' map-frame ATE, integrated and optimized
// (errors: before and after, per keyframe).
void printRobotRows(const std::vector<KeyframeRow>& keyframes, const std::vector<double>& before,
                    const std::vector<double>& after) {
  std::vector<std::string> order;  // as the robots first appear
  std::map<std::string, std::pair<std::vector<double>, std::vector<double>>> errors;
  for (std::size_t i = 0; i < keyframes.size(); ++i) {
    const auto [it, added] = errors.try_emplace(keyframes[i].robot);
    if (added) order.push_back(keyframes[i].robot);
    it->second.first.push_back(before[i]);
    it->second.second.push_back(after[i]);
  }
  if (order.size() < 2) return;
  for (const std::string& robot : order) {
    const auto& [b, a] = errors.at(robot);
    std::printf("| robot %s (%zu keyframes): map-frame ATE RMSE | %.3f m | %.3f m | |\n",
                robot.c_str(), b.size(), rmse(b), rmse(a));
  }
}

// The positions fitted to the truth by the rigid motion (Eigen's Umeyama), with a scale or not,
// that fits them best. Without scale the RMSE left is the error the map carries inside itself:
// a whole-map tilt or turn of the start's heading, which no revisit can observe, is not in it.
// With scale it also leaves out the map's scale error (the odometry's distance bias, e.g. the
// sensor's range scale), which no revisit observes either: loops close at any scale.
struct FitResult {
  double rmse = 0.0;   // [m]
  double scale = 1.0;  // estimate x scale ~ truth
};

FitResult fitToTruth(const std::vector<Eigen::Vector3d>& estimate,
                     const std::vector<Eigen::Vector3d>& truth, bool with_scale) {
  if (estimate.size() < 3) return {};
  Eigen::Matrix3Xd from(3, static_cast<Eigen::Index>(estimate.size()));
  Eigen::Matrix3Xd to(3, from.cols());
  for (std::size_t i = 0; i < estimate.size(); ++i) {
    from.col(static_cast<Eigen::Index>(i)) = estimate[i];
    to.col(static_cast<Eigen::Index>(i)) = truth[i];
  }
  const Eigen::Matrix4d fit = Eigen::umeyama(from, to, with_scale);
  const Eigen::Matrix3Xd moved =
      (fit.topLeftCorner<3, 3>() * from).colwise() + Eigen::Vector3d(fit.topRightCorner<3, 1>());
  return {std::sqrt((moved - to).colwise().squaredNorm().mean()),
          fit.topLeftCorner<3, 3>().determinant() > 0.0
              ? std::cbrt(fit.topLeftCorner<3, 3>().determinant())
              : 1.0};
}

// What a client output (poses_tum.txt) against the truth, in the map frame (no alignment):
// each pose is matched to the sequence's frame of the same stamp (times.txt).
struct ClientScore {
  std::size_t frames = 0;  // poses output
  double ate = 0.0;        // RMSE [m]
  double max = 0.0;
};

ClientScore scoreClient(const std::string& tum, const std::vector<double>& times,
                        const socc::Poses& gt) {
  std::vector<double> stamps;
  const socc::Poses poses = socc::readTumPoses(tum, &stamps);
  std::vector<double> errors;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const auto at = std::lower_bound(times.begin(), times.end(), stamps[i] - 1e-4);
    if (at == times.end() || std::abs(*at - stamps[i]) > 1e-3) continue;
    const auto seq = static_cast<std::size_t>(at - times.begin());
    if (seq >= gt.size()) continue;
    errors.push_back((poses[i].translation() - gt[seq].translation()).norm());
  }
  ClientScore out;
  out.frames = errors.size();
  out.ate = rmse(errors);
  out.max = errors.empty() ? 0.0 : *std::max_element(errors.begin(), errors.end());
  return out;
}

std::vector<double> readTimes(const std::string& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error("cannot read " + file);
  std::vector<double> times;
  double t = 0.0;
  while (in >> t) times.push_back(t);
  return times;
}

// The ground truth by seq, which must cover every seq scored.
class Truth {
 public:
  explicit Truth(socc::Poses poses) : poses_(std::move(poses)) {}
  const Eigen::Isometry3d& operator()(long seq) const {
    if (seq < 0 || static_cast<std::size_t>(seq) >= poses_.size())
      throw std::runtime_error("seq " + std::to_string(seq) + " beyond the ground truth");
    return poses_[static_cast<std::size_t>(seq)];
  }
  const socc::Poses& poses() const { return poses_; }

 private:
  socc::Poses poses_;
};

// Each keyframe against the truth: as integrated (before) and optimized (after).
struct KeyframeErrors {
  std::vector<double> before, after;  // position error [m]
  std::vector<double> z_before, z_after, xy_before, xy_after;
  std::vector<Eigen::Vector3d> truth_positions, odom_positions, optimized_positions;
  std::vector<double> travelled;  // along its robot's true path since its first keyframe [m]
};

KeyframeErrors scoreKeyframes(const std::vector<KeyframeRow>& keyframes, const Truth& truth) {
  KeyframeErrors e;
  e.travelled.assign(keyframes.size(), 0.0);
  for (std::size_t i = 0; i < keyframes.size(); ++i) {
    const KeyframeRow& k = keyframes[i];
    const Eigen::Vector3d before = k.odom.translation() - truth(k.seq).translation();
    const Eigen::Vector3d after = k.optimized.translation() - truth(k.seq).translation();
    e.before.push_back(before.norm());
    e.after.push_back(after.norm());
    e.z_before.push_back(before.z());
    e.z_after.push_back(after.z());
    e.xy_before.push_back(before.head<2>().norm());
    e.xy_after.push_back(after.head<2>().norm());
    e.truth_positions.push_back(truth(k.seq).translation());
    e.odom_positions.push_back(k.odom.translation());
    e.optimized_positions.push_back(k.optimized.translation());
    if (i > 0 && keyframes[i - 1].robot == k.robot)
      e.travelled[i] =
          e.travelled[i - 1] +
          (truth(k.seq).translation() - truth(keyframes[i - 1].seq).translation()).norm();
  }
  return e;
}

int countWrongClosures(const std::vector<ClosureRow>& closures, const Truth& truth, double wrong_m,
                       double wrong_deg) {
  int wrong = 0;
  for (const ClosureRow& c : closures) {
    const Eigen::Isometry3d error =
        (truth(c.seq_a).inverse() * truth(c.seq_b)).inverse() * c.relative;
    if (error.translation().norm() > wrong_m || angle(error) * 180.0 / M_PI > wrong_deg) {
      ++wrong;
      std::fprintf(stderr, "wrong closure %s %ld -> %s %ld: %.2f m %.2f deg\n", c.robot_a.c_str(),
                   c.seq_a, c.robot_b.c_str(), c.seq_b, error.translation().norm(),
                   angle(error) * 180.0 / M_PI);
    }
  }
  return wrong;
}

// Revisits: keyframe pairs the truth puts within revisit_m of each other after at least
// revisit_travel of path (or of two robots). Their surfaces are mapped twice when the estimate's
// relative pose errs by more than doubled_m.
struct Revisits {
  int count = 0, doubled_before = 0, doubled_after = 0;
  double max_before = 0.0;  // the largest contradiction a closure could observe [m]
  double shareBefore() const { return count ? static_cast<double>(doubled_before) / count : 0.0; }
  double shareAfter() const { return count ? static_cast<double>(doubled_after) / count : 0.0; }
};

Revisits scoreRevisits(const std::vector<KeyframeRow>& keyframes,
                       const std::vector<double>& travelled, const Truth& truth, double revisit_m,
                       double revisit_travel, double doubled_m) {
  Revisits r;
  for (std::size_t j = 0; j < keyframes.size(); ++j)
    for (std::size_t i = 0; i < j; ++i) {
      const KeyframeRow& a = keyframes[i];
      const KeyframeRow& b = keyframes[j];
      if (a.robot == b.robot && travelled[j] - travelled[i] < revisit_travel) continue;
      const Eigen::Isometry3d truth_ab = truth(a.seq).inverse() * truth(b.seq);
      if (truth_ab.translation().norm() > revisit_m) continue;
      ++r.count;
      const auto err = [&truth_ab](const Eigen::Isometry3d& pa, const Eigen::Isometry3d& pb) {
        return (truth_ab.inverse() * (pa.inverse() * pb)).translation().norm();
      };
      r.max_before = std::max(r.max_before, err(a.odom, b.odom));
      r.doubled_before += err(a.odom, b.odom) > doubled_m ? 1 : 0;
      r.doubled_after += err(a.optimized, b.optimized) > doubled_m ? 1 : 0;
    }
  return r;
}

double maxOf(const std::vector<double>& v) {
  return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end());
}

// The map-frame rows: ATE (per robot too), its vertical and horizontal parts, the map's tilt,
// its inner and scale errors.
void printMapRows(const std::vector<KeyframeRow>& keyframes, const KeyframeErrors& e, double gain,
                  double min_gain) {
  std::printf("| map-frame ATE RMSE (keyframes) | %.3f m | %.3f m (%.1fx lower) | >= %.0fx |\n",
              rmse(e.before), rmse(e.after), gain, min_gain);
  printRobotRows(keyframes, e.before, e.after);
  std::printf("| map-frame ATE max | %.3f m | %.3f m | |\n", maxOf(e.before), maxOf(e.after));
  std::printf("| of it vertical / horizontal (RMSE) | %.3f / %.3f m | %.3f / %.3f m | |\n",
              rmse(e.z_before), rmse(e.xy_before), rmse(e.z_after), rmse(e.xy_after));
  const TiltFit tilt = socc::bench::fitTilt(e.truth_positions, e.z_before);
  const TiltFit tilt_after = socc::bench::fitTilt(e.truth_positions, e.z_after);
  std::printf(
      "| vertical error as a tilted map: tilt, residual (RMSE) | %.2f deg, %.3f m | %.2f deg, "
      "%.3f m | |\n",
      tilt.degrees, tilt.residual, tilt_after.degrees, tilt_after.residual);
  std::printf(
      "| ATE RMSE after a rigid fit to the truth (the map's inner error) | %.3f m | %.3f m | |\n",
      fitToTruth(e.odom_positions, e.truth_positions, false).rmse,
      fitToTruth(e.optimized_positions, e.truth_positions, false).rmse);
  const FitResult scaled_before = fitToTruth(e.odom_positions, e.truth_positions, true);
  const FitResult scaled_after = fitToTruth(e.optimized_positions, e.truth_positions, true);
  // The map's size against the truth's: 1 / the fitted scale.
  std::printf(
      "| the map's scale error (no closure observes it), ATE RMSE after a fit with scale | "
      "%+.3f %%, %.3f m | %+.3f %%, %.3f m | |\n",
      100.0 * (1.0 / scaled_before.scale - 1.0), scaled_before.rmse,
      100.0 * (1.0 / scaled_after.scale - 1.0), scaled_after.rmse);
}

// The service's own figures (stats.txt); rows of counters older runs did not write are left out.
void printServiceRows(std::map<std::string, double>& stats, double km) {
  std::printf("| time to correct a loop (max) | | %.2f s | |\n", stats["max_correction_s"]);
  std::printf("| keyframe memory (of it, scans for rebuilds) | | %.1f MB/km (%.1f MB/km) | |\n",
              km > 0.0 ? stats["keyframe_bytes"] / 1e6 / km : 0.0,
              km > 0.0 ? stats["scan_bytes"] / 1e6 / km : 0.0);
  std::printf("| grid rebuilds (longest) | | %.0f (%.2f s, %.0f scans) | |\n", stats["rebuilds"],
              stats["max_rebuild_s"], stats["rebuild_keyframes"]);
  // Runs before region rebuilds (docs/consistency.md "Region rebuilds") wrote no sums.
  if (stats.count("rebuild_scans"))
    std::printf(
        "| rebuilds in all: worker time, scans integrated; grid copy kept for region rebuilds | "
        "| %.1f s, %.0f scans; %.1f MB | |\n",
        stats["rebuild_s"], stats["rebuild_scans"], stats["base_bytes"] / 1e6);
  // Counts of keyframes; each row only when the run wrote its counter.
  const auto ofKeyframes = [&stats](const char* figure, const char* key) {
    if (!stats.count(key)) return false;
    std::printf("| %s | | %.0f of %.0f | |\n", figure, stats[key], stats["keyframes"]);
    return true;
  };
  // Runs before reduction on arrival wrote scans_dropped: those keyframes lost their scans.
  if (!ofKeyframes("keyframes reduced on arrival (worker max_pending_scans behind)",
                   "scans_reduced_on_arrival"))
    ofKeyframes("keyframes whose scans were dropped (worker behind)", "scans_dropped");
  // Runs before gravity references (docs/consistency.md "Gravity reference") wrote no count.
  ofKeyframes("keyframes with a gravity reference (INTEGRATE gravity_sigma > 0)",
              "gravity_keyframes");
  if (stats.count("edge_checks"))
    std::printf(
        "| odometry edges scan to scan: registered / snaps (of them no closure: integrated) of "
        "checked, s per keyframe (max) | | %.0f / %.0f (%.0f) of %.0f, %.3f s (%.2f s) | |\n",
        stats["edge_registered"], stats["edge_snaps"], stats["edge_snaps_unclosed"],
        stats["edge_checks"],
        stats["edge_checks"] > 0.0 ? stats["edge_s"] / stats["edge_checks"] : 0.0,
        stats["edge_max_s"]);
}

struct ClientFiles {
  std::string with_tum, alone_tum, revised_tum, times;
};

// The client's output rows; returns how many times lower its ATE is with the service than
// alone (0: not both scored).
double printClientRows(const ClientFiles& files, const socc::Poses& gt) {
  if (files.with_tum.empty() || files.times.empty()) return 0.0;
  const std::vector<double> times = readTimes(files.times);
  const ClientScore with = scoreClient(files.with_tum, times, gt);
  ClientScore alone;
  if (!files.alone_tum.empty()) alone = scoreClient(files.alone_tum, times, gt);
  std::printf(
      "| client output: map-frame ATE RMSE / max (frames output of %zu) | %s | %.3f / "
      "%.3f m (%zu) | |\n",
      gt.size(),
      alone.frames
          ? (std::to_string(alone.ate).substr(0, 5) + " / " +
             std::to_string(alone.max).substr(0, 5) + " m (" + std::to_string(alone.frames) + ")")
                .c_str()
          : "not run",
      with.ate, with.max, with.frames);
  if (!files.revised_tum.empty()) {
    const ClientScore revised = scoreClient(files.revised_tum, times, gt);
    std::printf(
        "| client output revised by the graph: map-frame ATE RMSE / max (frames of %zu) | "
        "| %.3f / %.3f m (%zu) | |\n",
        gt.size(), revised.ate, revised.max, revised.frames);
  }
  return with.ate > 0.0 && alone.frames > 0 ? alone.ate / with.ate : 0.0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "bench_consistency_eval: scores map_server --consistency-dir output against the "
      "ground truth (docs/consistency.md)"};
  std::string dir, gt_file;
  double min_gain = 5.0, max_doubled = 0.0, wrong_m = 1.0, wrong_deg = 3.0, doubled_m = 0.5;
  double revisit_m = 4.0, revisit_travel = 50.0;
  app.add_option("--dir", dir, "map_server --consistency-dir")->required();
  app.add_option("--gt", gt_file, "ground truth, KITTI layout, LiDAR frame, line = seq")
      ->required();
  app.add_option("--min-gain", min_gain, "target: ATE after at least this many times lower")
      ->capture_default_str();
  app.add_option("--max-doubled", max_doubled, "target: share of revisits mapped twice")
      ->capture_default_str();
  app.add_option("--wrong-m", wrong_m, "a closure this far from the truth is wrong [m]")
      ->capture_default_str();
  app.add_option("--wrong-deg", wrong_deg, "... or turned this far from it [deg]")
      ->capture_default_str();
  app.add_option("--doubled-m", doubled_m,
                 "a revisit whose relative pose errs by more than this maps its surfaces twice [m]")
      ->capture_default_str();
  ClientFiles client;
  app.add_option("--client-tum", client.with_tum,
                 "the client's poses_tum.txt with the consistency service (map correction on)");
  app.add_option("--alone-tum", client.alone_tum, "the client's poses_tum.txt without it");
  app.add_option("--revised-tum", client.revised_tum,
                 "the client's poses_revised_tum.txt (its output revised by the pose graph at "
                 "the end of the run, docs/consistency.md \"The revised trajectory\")");
  app.add_option("--times", client.times, "the sequence's times.txt (stamps of the frames)");
  CLI11_PARSE(app, argc, argv);
  try {
    const Truth truth(socc::readKittiPoses(gt_file));
    const std::vector<KeyframeRow> keyframes = socc::bench::readKeyframes(dir + "/keyframes.txt");
    const std::vector<ClosureRow> closures = socc::bench::readClosures(dir + "/closures.txt");
    std::map<std::string, double> stats = readStats(dir + "/stats.txt");
    const KeyframeErrors errors = scoreKeyframes(keyframes, truth);
    const int wrong = countWrongClosures(closures, truth, wrong_m, wrong_deg);
    const Revisits revisits =
        scoreRevisits(keyframes, errors.travelled, truth, revisit_m, revisit_travel, doubled_m);
    const double km = stats["travelled_m"] / 1000.0;
    const double ate_before = rmse(errors.before), ate_after = rmse(errors.after);
    const double gain = ate_after > 0.0 ? ate_before / ate_after : INFINITY;
    std::printf("| figure | odometry alone | with consistency | target |\n|---|---|---|---|\n");
    std::printf("| keyframes / path | %zu / %.2f km | | |\n", keyframes.size(), km);
    printMapRows(keyframes, errors, gain, min_gain);
    std::printf(
        "| largest revisit relative pose error (what a closure can observe) | %.3f m | | |\n",
        revisits.max_before);
    std::printf(
        "| revisits mapped twice (> %.1f m) | %d of %d (%.0f %%) | %d of %d (%.0f %%) | <= %.0f %% "
        "|\n",
        doubled_m, revisits.doubled_before, revisits.count, 100.0 * revisits.shareBefore(),
        revisits.doubled_after, revisits.count, 100.0 * revisits.shareAfter(), 100.0 * max_doubled);
    std::printf("| closures verified / attempts | | %d / %.0f | |\n",
                static_cast<int>(closures.size()), stats["attempts"]);
    std::printf(
        "| candidates refused: explain too little / ambiguous / free space / no registration | | "
        "%.0f / %.0f / %.0f / %.0f | |\n",
        stats["candidates_refused_low_fitness"], stats["candidates_refused_ambiguous"],
        stats["candidates_refused_free_space"], stats["candidates_refused_no_registration"]);
    std::printf("| wrong closures (> %.1f m or %.0f deg) | | %d | 0 |\n", wrong_m, wrong_deg,
                wrong);
    printServiceRows(stats, km);
    const double client_gain = printClientRows(client, truth.poses());
    // With both client runs scored, the target is on what the client output (map correction).
    const double judged = client_gain > 0.0 ? client_gain : gain;
    const bool pass = wrong == 0 && judged >= min_gain && revisits.shareAfter() <= max_doubled;
    char client_text[64] = "client output not run alone";
    if (client_gain > 0.0)
      std::snprintf(client_text, sizeof client_text, "client output %.1fx", client_gain);
    std::printf(
        "%s: ATE %.3f -> %.3f m (%.1fx; %s), %d wrong closures, revisits mapped twice %.0f %% -> "
        "%.0f %%\n",
        pass ? "PASS" : "FAIL", ate_before, ate_after, gain, client_text, wrong,
        100.0 * revisits.shareBefore(), 100.0 * revisits.shareAfter());
    return pass ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_consistency_eval: %s\n", e.what());
    return 2;
  }
}
