// bench_map_scaling: how the map's memory and its integration and chunk query times grow with
// the map (docs/scaling.md). Integrates a KITTI-layout sequence (e.g. a long socc-sim drive)
// frame by frame at its GT poses into one SemanticOccupancyMap (0.5 m voxels, 100 m range, as
// the server's default) and prints a markdown row every --every frames: voxels, grid memory,
// bytes per voxel, the process's resident memory, mean integration time of the last frames and
// the time of a GET_CHUNK-like query (sphere around the current pose, odometry's features);
// at the end the time to write and read the map as a snapshot. No target is judged.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>

#include "socc/kitti_io.hpp"
#include "socc/labels.hpp"
#include "socc/map/semantic_occupancy_map.hpp"

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct Options {
  std::string kitti;
  int frames = 100000;
  int every = 50;
  double chunk_radius = 40.0;
  double voxel_size = 0.5;
  double max_range = 100.0;
};

double msSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// Resident set size of this process [MB] (/proc/self/status VmRSS).
double residentMb() {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);)
    if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  return 0.0;
}

socc::LabeledCloud loadCloud(const fs::path& bin, const fs::path& label) {
  socc::LabeledCloud cloud;
  cloud.points = socc::readKittiBin(bin);
  if (!label.empty())
    for (std::uint32_t raw : socc::readSemanticKittiLabels(label))
      cloud.labels.push_back(socc::mapSemanticKittiLabel(raw & 0xFFFFu));
  return cloud;
}

// Mean time of a few chunk queries around position (the odometry's fields).
std::pair<double, std::int32_t> timeChunk(const socc::map::SemanticOccupancyMap& map,
                                          const Eigen::Vector3d& position, double radius) {
  socc::map::ChunkQuery query;
  query.center = position;
  query.radius = radius;
  constexpr int kRepeats = 5;
  std::int32_t voxels = 0;
  const auto start = Clock::now();
  for (int i = 0; i < kRepeats; ++i) voxels = map.queryChunk(query).num_occupied;
  return {msSince(start) / kRepeats, voxels};
}

void printRow(const socc::map::SemanticOccupancyMap& map, int frames, double integrate_ms,
              const std::pair<double, std::int32_t>& chunk) {
  const socc::map::MapStats s = map.stats();
  std::printf("| %d | %.2f | %.2f | %lld | %.1f | %.0f | %.0f | %.1f | %.2f | %d |\n", frames,
              static_cast<double>(s.num_voxels) / 1e6, static_cast<double>(s.num_occupied) / 1e6,
              static_cast<long long>(s.num_blocks), static_cast<double>(s.memory_bytes) / 1e6,
              static_cast<double>(s.memory_bytes) / static_cast<double>(s.num_voxels), residentMb(),
              integrate_ms, chunk.first, chunk.second);
  std::fflush(stdout);
}

// Writes the map as a snapshot (fsynced, as map_server does) and reads it back: restart cost.
void timeSnapshot(const socc::map::SemanticOccupancyMap& map) {
  const fs::path file =
      fs::temp_directory_path() / ("bench_map_scaling." + std::to_string(::getpid()));
  auto start = Clock::now();
  map.save(file);
  const double save_ms = msSince(start);
  start = Clock::now();
  const auto loaded = socc::map::SemanticOccupancyMap::load(file);
  const double load_ms = msSince(start);
  std::printf("\nsnapshot: %.1f MB, written in %.0f ms, loaded in %.0f ms (%lld voxels)\n",
              static_cast<double>(fs::file_size(file)) / 1e6, save_ms, load_ms,
              static_cast<long long>(loaded.stats().num_voxels));
  fs::remove(file);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"bench_map_scaling: map memory, integration and chunk time vs map size"};
  Options o;
  app.add_option("--kitti", o.kitti, "KITTI-layout sequence with poses.txt and calib.txt")
      ->required()
      ->check(CLI::ExistingDirectory);
  app.add_option("--frames", o.frames, "frames to integrate (at most)")->capture_default_str();
  app.add_option("--every", o.every, "a row every N frames")->capture_default_str();
  app.add_option("--chunk-radius", o.chunk_radius, "query sphere [m]")->capture_default_str();
  app.add_option("--voxel-size", o.voxel_size)->capture_default_str();
  app.add_option("--max-range", o.max_range)->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  const socc::KittiSequence seq = socc::listKittiSequence(o.kitti);
  const socc::Poses poses = socc::readKittiLidarPoses(o.kitti);
  const std::size_t n =
      std::min({static_cast<std::size_t>(o.frames), seq.scans.size(), poses.size()});
  socc::map::MapConfig config;
  config.voxel_size = o.voxel_size;
  config.max_range = o.max_range;
  socc::map::SemanticOccupancyMap map(config);
  std::printf("%s: %zu frames, voxel %.2f m, range %.0f m, chunk sphere %.0f m\n\n",
              o.kitti.c_str(), n, o.voxel_size, o.max_range, o.chunk_radius);
  std::printf(
      "| frames | voxels (M) | occupied (M) | blocks | grid MB | bytes/voxel | RSS MB | "
      "integrate ms (last %d) | chunk ms | chunk voxels "
      "|\n|---|---|---|---|---|---|---|---|---|---|\n",
      o.every);
  double window_ms = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const socc::LabeledCloud cloud = loadCloud(seq.scans[i], seq.labels[i]);
    const auto start = Clock::now();
    map.integrate(poses[i], cloud);
    window_ms += msSince(start);
    if ((i + 1) % static_cast<std::size_t>(o.every) != 0 && i + 1 != n) continue;
    const int in_window = static_cast<int>(i % static_cast<std::size_t>(o.every)) + 1;
    printRow(map, static_cast<int>(i + 1), window_ms / in_window,
             timeChunk(map, poses[i].translation(), o.chunk_radius));
    window_ms = 0.0;
  }
  timeSnapshot(map);
  return 0;
}
