// Integration speed and memory of the semantic occupancy grid vs OctoMap on real KITTI scans.
// Prints a markdown table; targets: <= 30 ms/scan and >= 5x faster than OctoMap's
// insertPointCloud (same resolution and max range, discretize = true), both in the same run.
#include <octomap/OcTree.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <numeric>

#include "socc/kitti_io.hpp"
#include "socc/map/semantic_occupancy_map.hpp"
#include "socc/progress_bar.hpp"

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct Timing {
  double mean = 0, median = 0, max = 0;
};

Timing summarise(std::vector<double> ms) {
  Timing t;
  if (ms.empty()) return t;
  t.mean = std::accumulate(ms.begin(), ms.end(), 0.0) / static_cast<double>(ms.size());
  t.max = *std::max_element(ms.begin(), ms.end());
  std::sort(ms.begin(), ms.end());
  t.median = ms[ms.size() / 2];
  return t;
}

double msSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Benchmark: integrate real KITTI scans (GT poses, LiDAR frame) into the semantic occupancy "
      "grid and into OctoMap's OcTree::insertPointCloud in the same run; prints ms/scan, memory, "
      "the speed ratio and PASS/FAIL against the targets (<= 30 ms/scan, >= 5x OctoMap)."};
  std::string data = (fs::path(SOCC_SOURCE_DIR) / "../shared/data/kitti_00_first16").string();
  int frames = 16;
  int repeat = 3;
  double voxel_size = 0.5, max_range = 100.0;
  bool strict = false, skip_octomap = false;
  app.add_option("--data", data, "KITTI-layout directory (velodyne/, poses.txt, calib.txt)")
      ->capture_default_str();
  app.add_option("--frames", frames, "number of scans to integrate")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--repeat", repeat,
                 "runs per mapper (fresh map each); per scan the fastest run counts, which "
                 "filters out preemption on a shared machine")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--voxel-size", voxel_size, "voxel size [m]")->capture_default_str();
  app.add_option("--max-range", max_range, "max range [m]")->capture_default_str();
  app.add_flag("--skip-octomap", skip_octomap, "only run our grid (no ratio)");
  app.add_flag("--strict", strict, "exit 1 when a target is missed");
  CLI11_PARSE(app, argc, argv);

  if (!fs::exists(fs::path(data) / "velodyne")) {
    std::cout << "SKIP: data not found at " << data << " (pass --data DIR)\n";
    return 0;
  }
  const socc::KittiSequence seq = socc::listKittiSequence(data);
  const socc::Poses poses = socc::readKittiLidarPoses(data);
  const std::size_t n =
      std::min({static_cast<std::size_t>(frames), seq.scans.size(), poses.size()});
  std::vector<socc::LabeledCloud> clouds(n);
  std::size_t total_points = 0;
  for (std::size_t i = 0; i < n; ++i) {
    clouds[i].points = socc::readKittiBin(seq.scans[i]);
    total_points += clouds[i].size();
  }

  socc::map::MapConfig config;
  config.voxel_size = voxel_size;
  config.max_range = max_range;
  std::vector<double> ours_ms(n, 1e300);
  socc::map::MapStats stats;
  for (int run = 0; run < repeat; ++run) {
    socc::map::SemanticOccupancyMap map(config);
    socc::ProgressBar bar("socc grid run " + std::to_string(run + 1), n);
    for (std::size_t i = 0; i < n; ++i) {
      const auto start = Clock::now();
      map.integrate(poses[i], clouds[i]);
      const double ms = msSince(start);
      ours_ms[i] = std::min(ours_ms[i], ms);
      bar.tick(std::to_string(ms) + " ms");
    }
    stats = map.stats();
  }

  std::vector<double> octo_ms;
  std::size_t octo_bytes = 0, octo_nodes = 0;
  if (!skip_octomap) {
    std::vector<octomap::Pointcloud> octo_clouds(n);  // map frame, built outside the timing
    for (std::size_t i = 0; i < n; ++i) {
      octo_clouds[i].reserve(clouds[i].size());
      for (const auto& p : clouds[i].points) {
        const Eigen::Vector3d q = poses[i] * p.cast<double>();
        octo_clouds[i].push_back(static_cast<float>(q.x()), static_cast<float>(q.y()),
                                 static_cast<float>(q.z()));
      }
    }
    octo_ms.assign(n, 1e300);
    for (int run = 0; run < repeat; ++run) {
      octomap::OcTree tree(voxel_size);
      socc::ProgressBar bar("octomap run " + std::to_string(run + 1), n);
      for (std::size_t i = 0; i < n; ++i) {
        const Eigen::Vector3d o = poses[i].translation();
        const octomap::point3d origin(static_cast<float>(o.x()), static_cast<float>(o.y()),
                                      static_cast<float>(o.z()));
        const auto start = Clock::now();
        tree.insertPointCloud(octo_clouds[i], origin, max_range, false, true);
        const double ms = msSince(start);
        octo_ms[i] = std::min(octo_ms[i], ms);
        bar.tick(std::to_string(ms) + " ms");
      }
      octo_bytes = tree.memoryUsage();
      octo_nodes = tree.size();
    }
  }

  const Timing ours = summarise(ours_ms), octo = summarise(octo_ms);
  std::printf(
      "\n## Map integration: %zu KITTI scans (%.0f points/scan), %.2f m voxels, %.0f m range, "
      "best of %d runs per scan\n\n",
      n, static_cast<double>(total_points) / static_cast<double>(n), voxel_size, max_range, repeat);
  std::printf("| mapper | ms/scan mean | median | max | voxels / nodes | memory [MB] |\n");
  std::printf("|---|---:|---:|---:|---:|---:|\n");
  std::printf("| socc grid (raycast, stats, semantics) | %.1f | %.1f | %.1f | %lld | %.1f |\n",
              ours.mean, ours.median, ours.max, static_cast<long long>(stats.num_voxels),
              static_cast<double>(stats.memory_bytes) / 1e6);
  if (!skip_octomap)
    std::printf("| OctoMap insertPointCloud (discretize) | %.1f | %.1f | %.1f | %zu | %.1f |\n",
                octo.mean, octo.median, octo.max, octo_nodes,
                static_cast<double>(octo_bytes) / 1e6);

  bool pass = true;
  const bool fast = ours.mean <= 30.0;
  pass &= fast;
  std::printf("\n- target <= 30 ms/scan (mean): %.1f ms -> %s\n", ours.mean,
              fast ? "PASS" : "FAIL");
  if (!skip_octomap) {
    const double ratio = octo.mean / ours.mean;
    const bool faster = ratio >= 5.0;
    pass &= faster;
    std::printf("- target >= 5x faster than OctoMap: %.1fx -> %s\n", ratio,
                faster ? "PASS" : "FAIL");
  }
  std::printf("- occupied voxels: %lld, blocks: %lld\n", static_cast<long long>(stats.num_occupied),
              static_cast<long long>(stats.num_blocks));
  return strict && !pass ? 1 : 0;
}
