// bench_gravity_graph: what gravity priors (docs/consistency.md "Gravity reference") would have
// done to a run's pose graph, offline. Reads map_server --consistency-dir output (keyframes.txt:
// each keyframe as integrated; closures.txt: the accepted closures) and the sequence's ground
// truth, builds the service's graph again (nodes at the integrated poses, odometry edges with
// the default sigmas, the closures at the loop sigmas, the first robot's first keyframe fixed,
// a weak prior on each later robot's first), and optimizes it without and with a gravity prior
// on every keyframe: the truth's +z in the keyframe's frame turned by a random error of --noise
// rad, weighed with --sigma. Prints the map-frame ATE of the keyframes (no alignment), vertical /
// horizontal, and the tilt of the vertical error, for each. The edge uncertainties can be
// changed (--odometry-sigma-*, --loop-sigma-*, and factors on the odometry edges' yaw, roll and
// pitch, and along-track sigmas): the sweep of docs/consistency.md "What is left on the full
// drive". (socc-sim's truth is the first LiDAR frame, whose +z is not the simulated world's up
// exactly: 0.11 deg apart on the KITTI-00 shape; the priors here are exact in the truth's frame.)
//
// Differs from the live service: every closure is in the graph from the start (no chi-square
// test, no order), the odometry edges are the integrated relative poses (no scan-to-scan ones)
// with the straight distance for their sigma (the service: path length).
#include <CLI/CLI.hpp>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "consistency_output.hpp"
#include "consistency_params.hpp"
#include "pose_graph.hpp"
#include "socc/kitti_io.hpp"

namespace {

using socc::consistency::PoseGraph;

using socc::bench::KeyframeRow;

struct Score {
  double rmse = 0.0, vertical = 0.0, horizontal = 0.0, tilt_deg = 0.0;
};

Score score(const PoseGraph& g, const std::vector<Eigen::Isometry3d>& truth) {
  Score s;
  std::vector<Eigen::Vector3d> positions;
  std::vector<double> z_error;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const Eigen::Vector3d t = truth[i].translation();
    const Eigen::Vector3d e = g.pose(static_cast<int>(i)).translation() - t;
    s.vertical += e.z() * e.z();
    s.horizontal += e.head<2>().squaredNorm();
    positions.push_back(t);
    z_error.push_back(e.z());
  }
  const double n = static_cast<double>(truth.size());
  s.rmse = std::sqrt((s.vertical + s.horizontal) / n);
  s.vertical = std::sqrt(s.vertical / n);
  s.horizontal = std::sqrt(s.horizontal / n);
  s.tilt_deg = socc::bench::fitTilt(positions, z_error).degrees;
  return s;
}

// Experiment knobs over the service's edge uncertainties: factors on the yaw (rotation about
// the sensor's z) and along-track (sensor x) sigmas of the odometry edges.
struct EdgeModel {
  double yaw_factor = 1.0;
  double along_factor = 1.0;
  double tilt_factor = 1.0;  // roll and pitch (rotation about the sensor's x and y)
};

socc::consistency::Matrix6d odometryInformation(const socc::consistency::ConsistencyParams& params,
                                                double d, const EdgeModel& model) {
  const double st = params.odometry_sigma_t + params.odometry_sigma_t_per_m * d;
  const double sr = params.odometry_sigma_r + params.odometry_sigma_r_per_m * d;
  socc::consistency::Matrix6d info = socc::consistency::isotropicInformation(st, sr);
  info(0, 0) /= model.along_factor * model.along_factor;
  info(5, 5) /= model.yaw_factor * model.yaw_factor;
  info(3, 3) /= model.tilt_factor * model.tilt_factor;
  info(4, 4) /= model.tilt_factor * model.tilt_factor;
  return info;
}

// The service's graph over the run's keyframes (see the file comment).
PoseGraph buildGraph(const std::vector<KeyframeRow>& rows, const std::string& closures_file,
                     const socc::consistency::ConsistencyParams& params, const EdgeModel& model) {
  PoseGraph g;
  std::map<std::string, int> last;  // robot: its last node
  std::map<std::pair<std::string, long>, int> node;
  for (const KeyframeRow& r : rows) {
    const int id = g.addNode(r.odom);
    node[{r.robot, r.seq}] = id;
    const auto previous = last.find(r.robot);
    if (previous == last.end()) {
      g.addPrior({id, r.odom,
                  socc::consistency::isotropicInformation(params.joined_prior_sigma_t,
                                                          params.joined_prior_sigma_r),
                  last.empty()});
    } else {
      const Eigen::Isometry3d rel =
          rows[static_cast<std::size_t>(previous->second)].odom.inverse() * r.odom;
      const double d = rel.translation().norm();
      g.addEdge({previous->second, id, rel, odometryInformation(params, d, model)});
    }
    last[r.robot] = id;
  }
  for (const socc::bench::ClosureRow& c : socc::bench::readClosures(closures_file)) {
    const auto a = node.find({c.robot_a, c.seq_a}), b = node.find({c.robot_b, c.seq_b});
    if (a == node.end() || b == node.end()) continue;
    g.addEdge({a->second, b->second, c.relative,
               socc::consistency::isotropicInformation(params.loop_sigma_t, params.loop_sigma_r)});
  }
  return g;
}

void printRow(const char* name, const Score& s, double seconds) {
  std::printf("| %s | %.3f m | %.3f / %.3f m | %.3f deg | %.2f s |\n", name, s.rmse, s.vertical,
              s.horizontal, s.tilt_deg, seconds);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "bench_gravity_graph: a run's pose graph optimized without and with gravity priors "
      "from the ground truth (docs/consistency.md \"Gravity reference\")"};
  std::string dir, gt_file;
  double sigma = 0.001, noise = 0.001;
  unsigned seed = 1;
  socc::consistency::ConsistencyParams params;
  EdgeModel model;
  app.add_option("--odometry-sigma-t", params.odometry_sigma_t)->capture_default_str();
  app.add_option("--odometry-sigma-t-per-m", params.odometry_sigma_t_per_m)->capture_default_str();
  app.add_option("--odometry-sigma-r", params.odometry_sigma_r)->capture_default_str();
  app.add_option("--odometry-sigma-r-per-m", params.odometry_sigma_r_per_m)->capture_default_str();
  app.add_option("--loop-sigma-t", params.loop_sigma_t)->capture_default_str();
  app.add_option("--loop-sigma-r", params.loop_sigma_r)->capture_default_str();
  app.add_option("--yaw-factor", model.yaw_factor, "on the odometry edges' yaw sigma")
      ->capture_default_str();
  app.add_option("--tilt-factor", model.tilt_factor, "on the odometry edges' roll, pitch sigmas")
      ->capture_default_str();
  app.add_option("--along-factor", model.along_factor, "on the odometry edges' x sigma")
      ->capture_default_str();
  app.add_option("--dir", dir, "map_server --consistency-dir")->required();
  app.add_option("--gt", gt_file, "ground truth, KITTI layout, LiDAR frame, z up, line = seq")
      ->required();
  app.add_option("--sigma", sigma, "sigma of the gravity priors [rad]")->capture_default_str();
  app.add_option("--noise", noise, "error of the simulated up directions, per axis [rad]")
      ->capture_default_str();
  app.add_option("--seed", seed, "of the errors")->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  try {
    const std::vector<KeyframeRow> rows = socc::bench::readKeyframes(dir + "/keyframes.txt");
    const socc::Poses gt = socc::readKittiPoses(gt_file);
    std::vector<Eigen::Isometry3d> truth;
    for (const KeyframeRow& r : rows) {
      if (r.seq < 0 || static_cast<std::size_t>(r.seq) >= gt.size())
        throw std::runtime_error("keyframe seq " + std::to_string(r.seq) + " not in the truth");
      truth.push_back(gt[static_cast<std::size_t>(r.seq)]);
    }
    const PoseGraph raw = buildGraph(rows, dir + "/closures.txt", params, model);
    PoseGraph without = raw, with = raw;
    const double s_without = without.optimize(200).seconds;
    std::mt19937 rng(seed);
    std::normal_distribution<double> error(0.0, noise);
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const Eigen::Vector3d e(error(rng), error(rng), 0.0);  // a tilt about the world's x, y
      const Eigen::Vector3d up_world =
          e.norm() > 0.0 ? Eigen::AngleAxisd(e.norm(), e.normalized()) * Eigen::Vector3d::UnitZ()
                         : Eigen::Vector3d::UnitZ();
      with.addGravityPrior({static_cast<int>(i), truth[i].linear().transpose() * up_world, sigma});
    }
    const double s_with = with.optimize(200).seconds;
    std::printf("%zu keyframes, %zu edges; gravity sigma %.4f rad, error %.4f rad per axis\n\n",
                rows.size(), raw.edges().size(), sigma, noise);
    std::printf(
        "| graph | map-frame ATE RMSE | vertical / horizontal | tilt of the vertical error "
        "| optimization |\n|---|---|---|---|---|\n");
    printRow("as integrated", score(raw, truth), 0.0);
    printRow("optimized, closures only", score(without, truth), s_without);
    printRow("optimized, closures and gravity priors", score(with, truth), s_with);
    std::printf("\nthe map's up direction estimated: %.4f deg from +z\n",
                std::acos(std::clamp(with.up()->z(), -1.0, 1.0)) * 180.0 / M_PI);
  } catch (const std::exception& e) {
    std::cerr << "bench_gravity_graph: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
