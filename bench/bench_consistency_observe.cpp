// bench_consistency_observe: what ConsistencyService::observe costs the map's (LCM) thread per
// keyframe (docs/consistency.md, "Limits"): the full cloud copied for the worker, and the cloud
// reduced on arrival to what the worker keeps of it (keyframe_reduction.hpp), done there only
// while max_pending_scans full clouds wait. Real HDL-64 scans (KITTI 00's first 16, ~120k points;
// frame 0 with its SemanticKITTI labels, the others unlabeled); the worker is held, so only the
// observing thread is timed. No target is judged; exit 77 when the data is absent.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "consistency_service.hpp"
#include "socc/kitti_io.hpp"
#include "socc/labels.hpp"

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using socc::LabeledCloud;
using socc::consistency::ConsistencyParams;
using socc::consistency::ConsistencyService;

struct Options {
  std::string data = std::string(SOCC_SHARED_DATA_DIR) + "/kitti_00_first16";
  int passes = 4;
  bool smoke = false;
};

std::vector<LabeledCloud> loadScans(const fs::path& root, std::size_t max_scans) {
  const socc::KittiSequence seq = socc::listKittiSequence(root);
  std::vector<LabeledCloud> scans;
  for (std::size_t i = 0; i < seq.scans.size() && i < max_scans; ++i) {
    LabeledCloud cloud;
    cloud.points = socc::readKittiBin(seq.scans[i]);
    cloud.labels.assign(cloud.points.size(), 0);
    if (!seq.labels[i].empty()) {
      const std::vector<std::uint32_t> raw = socc::readSemanticKittiLabels(seq.labels[i]);
      for (std::size_t k = 0; k < raw.size() && k < cloud.labels.size(); ++k)
        cloud.labels[k] = socc::mapSemanticKittiLabel(raw[k]);
    }
    scans.push_back(std::move(cloud));
  }
  return scans;
}

double percentile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(p * static_cast<double>(v.size() - 1))];
}

// Milliseconds of each observe() of scans (passes times over), every one a keyframe, the worker
// held; max_pending_scans decides whether it copies or reduces.
struct Timing {
  std::vector<double> all_ms;
  std::vector<double> frame0_ms;
  int reduced = 0;
};

Timing timeObserve(const std::vector<LabeledCloud>& scans, int passes, int max_pending_scans) {
  ConsistencyParams params;
  params.enabled = true;
  params.keyframe_distance = 0.0;  // every integration is a keyframe
  params.max_pending_scans = max_pending_scans;
  ConsistencyService service(params, socc::map::MapConfig{});
  service.hold(true);
  // The first call of the reducing service still copies (room for one cloud): left out.
  const bool skip_first = max_pending_scans == 1;
  Timing t;
  std::int64_t seq = 0;
  for (int pass = 0; pass < passes; ++pass)
    for (std::size_t i = 0; i < scans.size(); ++i, ++seq) {
      Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
      pose.translation().x() = static_cast<double>(seq);
      const auto start = Clock::now();
      service.observe("bench", seq, seq, pose, scans[i]);
      const double ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
      if (skip_first && seq == 0) continue;
      t.all_ms.push_back(ms);
      if (i == 0) t.frame0_ms.push_back(ms);
    }
  t.reduced = service.stats().scans_reduced_on_arrival;
  return t;  // destroyed held: nothing queued is processed
}

// Milliseconds of reduceScan alone without the rebuild scan (correct_grid off): the matching
// points' share of the reduction.
Timing timePointsOnly(const std::vector<LabeledCloud>& scans, int passes) {
  ConsistencyParams params;
  params.correct_grid = false;
  Timing t;
  for (int pass = 0; pass < passes; ++pass)
    for (std::size_t i = 0; i < scans.size(); ++i) {
      const auto start = Clock::now();
      const socc::consistency::ReducedScan r = socc::consistency::reduceScan(scans[i], params);
      t.all_ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
      if (i == 0) t.frame0_ms.push_back(t.all_ms.back());
      t.reduced += r.points.empty() ? 0 : 1;
    }
  return t;
}

void printRow(const char* what, const Timing& t) {
  std::printf("| %s | %zu | %.2f | %.2f | %.2f | %.2f |\n", what, t.all_ms.size(),
              percentile(t.all_ms, 0.5), percentile(t.all_ms, 0.9), percentile(t.all_ms, 1.0),
              t.frame0_ms.empty() ? 0.0 : percentile(t.frame0_ms, 0.5));
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"bench_consistency_observe: the map thread's cost per keyframe, copied or reduced"};
  app.add_option("--data", o.data, "KITTI-layout directory (velodyne/*.bin)")
      ->capture_default_str();
  app.add_option("--passes", o.passes, "passes over the scans")->capture_default_str();
  app.add_flag("--smoke", o.smoke, "2 scans, 1 pass (CI: it still runs)");
  CLI11_PARSE(app, argc, argv);
  if (!fs::is_directory(fs::path(o.data) / "velodyne")) {
    std::fprintf(stderr, "bench_consistency_observe: no scans in %s\n", o.data.c_str());
    return 77;
  }
  const std::vector<LabeledCloud> scans = loadScans(o.data, o.smoke ? 2 : 16);
  if (o.smoke) o.passes = 1;
  std::size_t points = 0;
  for (const LabeledCloud& s : scans) points += s.size();
  const socc::consistency::ReducedScan reduced = socc::consistency::reduceScan(scans[0], {});
  std::printf(
      "%zu scans, %.0f points on average; frame 0: %zu points = %.2f MB as observed "
      "(points, labels), %.2f MB reduced (%zu matching points, %zu scan points)\n\n",
      scans.size(), static_cast<double>(points) / static_cast<double>(scans.size()),
      scans[0].size(), static_cast<double>(scans[0].size() * 13) / 1e6,
      static_cast<double>(reduced.bytes()) / 1e6, reduced.points.size(), reduced.scan.size());
  const Timing copied = timeObserve(scans, o.passes, 1 << 20);
  const Timing reducing = timeObserve(scans, o.passes, 1);
  std::printf(
      "| observe() of a keyframe | calls | median ms | p90 ms | max ms | frame 0 (labeled) "
      "median ms |\n|---|---|---|---|---|---|\n");
  printRow("cloud copied for the worker", copied);
  printRow("cloud reduced on arrival (worker max_pending_scans behind)", reducing);
  printRow("of it: the matching points alone (reduceScan without correct_grid)",
           timePointsOnly(scans, o.passes));
  if (reducing.reduced != static_cast<int>(reducing.all_ms.size())) {
    std::fprintf(stderr, "bench_consistency_observe: %d of %zu reduced\n", reducing.reduced,
                 reducing.all_ms.size());
    return 1;
  }
  return 0;
}
