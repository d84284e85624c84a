// Odometry client benchmark: per-stage ms/frame and end-to-end Hz of the full pipeline
// (preprocess, registration target, register, Integrate) against a real map_server process over
// UDP multicast on loopback, on a KITTI-layout sequence, side by side with a baseline odometry
// binary run on the same scans in the same run (--baseline, e.g. a KISS-ICP runner built outside
// the repository). Prints markdown tables and PASS/FAIL against the targets of
// odom_client/README.md "Performance"; exits 1 when one is missed.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>
#include <random>
#include <string>

#include "odom_child_process.hpp"
#include "socc/odom/odom_runner.hpp"

namespace fs = std::filesystem;
using namespace socc::odom;

namespace {

struct Column {
  const char* name;
  double FrameStats::*field;
};

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1))];
}

struct Options {
  std::string data = std::string(SOCC_SHARED_DATA_DIR) + "/kitti_00_first16";
  std::string server_bin = SOCC_MAP_SERVER_BIN;
  std::string config_file;
  std::string baseline;        // command printing "fps=F" for the same data (DIR appended)
  double min_ratio = 1.2;      // socc end to end / baseline fps
  double min_hz = 35.0;        // without a baseline
  double max_p99_ratio = 3.0;  // p99 / median frame time
  double max_chunk_kib = 300.0;
  double max_upload_bytes = 1.0e6;
  int passes = 2;
  bool smoke = false;
  OdomConfig config;
};

void addOptions(CLI::App& app, Options& o) {
  app.add_option("--data", o.data, "KITTI-layout directory")->capture_default_str();
  app.add_option("--map-server", o.server_bin, "map_server executable")->capture_default_str();
  app.add_option("--passes", o.passes, "runs over the data, each with a fresh server")
      ->capture_default_str()
      ->check(CLI::Range(1, 100));
  app.add_option("--config", o.config_file, "odom_client YAML (default: built-in defaults)")
      ->check(CLI::ExistingFile);
  app.add_option("--baseline", o.baseline,
                 "baseline odometry command run on the same data (the data directory is "
                 "appended); it must print fps=F, e.g. a KISS-ICP runner built outside the repo");
  app.add_option("--min-ratio", o.min_ratio, "target: socc Hz >= this x baseline fps")
      ->capture_default_str();
  app.add_option("--min-hz", o.min_hz, "target without a baseline: socc Hz >= this")
      ->capture_default_str();
  app.add_option("--max-chunk-kib", o.max_chunk_kib, "target: mean chunk traffic [KiB/frame]")
      ->capture_default_str();
  app.add_option("--max-upload-bytes", o.max_upload_bytes,
                 "target: mean Integrate request [bytes/frame]")
      ->capture_default_str();
  app.add_flag("--smoke", o.smoke, "one pass, targets not judged (CI: the benchmark must run)");
}

// What the passes measured: frame rows (without each pass's first frame), frames and wall time
// of whole passes, chunks fetched again.
struct Measured {
  std::vector<FrameStats> rows;
  double frames = 0.0, wall = 0.0;
  std::int64_t refetched = 0;
};

// One pass over the data against a fresh map_server on a random private multicast group.
// False when the server did not answer.
bool runPass(const Options& o, unsigned seed, Measured& out) {
  const std::string url = "udpm://239.255." + std::to_string(1 + seed % 250) + "." +
                          std::to_string(1 + (seed / 250) % 250) + ":" +
                          std::to_string(40000 + (seed / 62500) % 10000) +
                          "?ttl=0&recv_buf_size=67108864";
  const fs::path log_file =
      fs::temp_directory_path() / ("bench_odometry_server_" + std::to_string(seed) + ".log");
  socc::testing::ChildProcess server(
      {o.server_bin, "--lcm-url", url, "--quiet", "--status-period", "0", "--config",
       SOCC_BENCH_SERVER_CONFIG},  // without the per-robot rate limits: a replay at full speed
      log_file);
  socc::rpc::ClientOptions options;
  options.lcm_url = url;
  options.client_id = "bench";
  socc::rpc::MapClient client(options);
  if (!client.getStats().ok()) {
    std::fprintf(stderr, "bench_odometry: map_server did not answer (log: %s)\n", log_file.c_str());
    return false;
  }
  const auto source = openKittiDirectory(o.data, {});
  FrameLog log;
  RunOptions run;
  run.progress = false;
  OdomRunner runner(o.config, client, run);
  runner.run(*source, log);
  // The first frame of each pass builds the map from nothing: not representative.
  out.rows.insert(out.rows.end(), log.rows().begin() + 1, log.rows().end());
  out.frames += static_cast<double>(log.frames());
  out.wall += runner.wallSeconds();
  out.refetched += runner.refetchedChunks();
  fs::remove(log_file);
  return true;
}

// Prints the per-stage table; returns the mean registration time [ms].
double printStages(const std::vector<FrameStats>& rows) {
  const Column columns[] = {
      {"preprocess (read, filter, times)", &FrameStats::preprocess_ms},
      {"registration target (wait + overlay)", &FrameStats::fetch_ms},
      {"register", &FrameStats::register_ms},
      {"wait for the previous frame's Integrate + chunk", &FrameStats::wait_ms},
      {"total (frame period)", &FrameStats::total_ms},
      {"GET_CHUNK round trip (worker thread)", &FrameStats::chunk_ms},
      {"INTEGRATE round trip (worker thread)", &FrameStats::integrate_ms}};
  std::printf("| stage | mean ms | median ms | p99 ms | max ms |\n|---|---|---|---|---|\n");
  double register_mean = 0.0;
  for (const Column& c : columns) {
    std::vector<double> v;
    for (const auto& r : rows) v.push_back(r.*c.field);
    double mean = 0.0;
    for (double x : v) mean += x;
    mean /= std::max<std::size_t>(v.size(), 1);
    if (c.field == &FrameStats::register_ms) register_mean = mean;
    std::printf("| %s | %.2f | %.2f | %.2f | %.2f |\n", c.name, mean, percentile(v, 0.5),
                percentile(v, 0.99), v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()));
  }
  return register_mean;
}

// Mean traffic per frame [bytes].
struct Traffic {
  double chunk = 0.0, upload = 0.0;
};

Traffic printMetrics(const Measured& m, double hz) {
  double received = 0.0, sent = 0.0, voxels = 0.0, iterations = 0.0, points = 0.0;
  for (const auto& r : m.rows) {
    received += static_cast<double>(r.bytes_received);
    sent += static_cast<double>(r.bytes_sent);
    voxels += static_cast<double>(r.chunk_voxels);
    iterations += r.iterations;
    points += static_cast<double>(r.downsampled_points);
  }
  const double n = std::max<double>(static_cast<double>(m.rows.size()), 1.0);
  std::printf("\n| metric | value |\n|---|---|\n");
  std::printf("| end-to-end rate (all frames, server included) | %.1f Hz |\n", hz);
  std::printf("| chunk traffic | %.0f KiB/frame, map of %.0f voxels |\n", received / n / 1024.0,
              voxels / n);
  std::printf("| Integrate upload | %.0f KiB/frame |\n", sent / n / 1024.0);
  std::printf("| registered points | %.0f/frame, %.1f iterations |\n", points / n, iterations / n);
  std::printf("| chunks fetched again (older than the previous Integrate) | %lld |\n",
              static_cast<long long>(m.refetched));
  return {received / n, sent / n};
}

// The baseline's fps on the same data: runs `command DIR` and reads "fps=F" from its output.
std::optional<double> baselineFps(const std::string& command, const std::string& data) {
  const std::string line = command + " '" + data + "' 2>&1";
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(line.c_str(), "r"), pclose);
  if (!pipe) return std::nullopt;
  std::string output;
  std::array<char, 4096> buf{};
  while (std::fgets(buf.data(), static_cast<int>(buf.size()), pipe.get()) != nullptr)
    output += buf.data();
  const std::size_t at = output.find("fps=");
  char* end = nullptr;
  const double fps = at == std::string::npos ? 0.0 : std::strtod(output.c_str() + at + 4, &end);
  if (at == std::string::npos || end == output.c_str() + at + 4 || !(fps > 0.0)) {
    std::fprintf(stderr, "bench_odometry: the baseline printed no fps=F:\n%s\n", output.c_str());
    return std::nullopt;
  }
  return fps;
}

double frameTimePercentile(const std::vector<FrameStats>& rows, double q) {
  std::vector<double> v;
  for (const auto& r : rows) v.push_back(r.total_ms);
  return percentile(v, q);
}

// PASS/FAIL lines; true when every target is met.
bool judge(const Options& o, double register_mean, double hz, std::optional<double> baseline,
           const std::vector<FrameStats>& rows, const Traffic& traffic) {
  bool all = true;
  const auto line = [&all](const std::string& what, bool ok) {
    std::printf("- %s -> %s\n", what.c_str(), ok ? "PASS" : "FAIL");
    all = all && ok;
  };
  char buf[256];
  std::snprintf(buf, sizeof(buf), "target registration <= 20 ms/frame (mean): %.1f", register_mean);
  line(buf, register_mean <= 20.0);
  if (baseline) {
    std::snprintf(buf, sizeof(buf),
                  "target end to end >= %.1fx the baseline (%.1f fps): %.1f Hz = %.2fx",
                  o.min_ratio, *baseline, hz, hz / *baseline);
    line(buf, hz >= o.min_ratio * *baseline);
  } else {
    std::snprintf(buf, sizeof(buf), "target end to end >= %.0f Hz (no baseline given): %.1f Hz",
                  o.min_hz, hz);
    line(buf, hz >= o.min_hz);
  }
  const double median = frameTimePercentile(rows, 0.5), p99 = frameTimePercentile(rows, 0.99);
  std::snprintf(buf, sizeof(buf), "target frame time p99 <= %.0fx median: %.1f / %.1f ms = %.2fx",
                o.max_p99_ratio, p99, median, median > 0.0 ? p99 / median : 0.0);
  line(buf, p99 <= o.max_p99_ratio * median);
  std::snprintf(buf, sizeof(buf), "target chunk traffic <= %.0f KiB/frame: %.0f", o.max_chunk_kib,
                traffic.chunk / 1024.0);
  line(buf, traffic.chunk <= o.max_chunk_kib * 1024.0);
  std::snprintf(buf, sizeof(buf), "target Integrate upload <= %.0f bytes/frame: %.0f",
                o.max_upload_bytes, traffic.upload);
  line(buf, traffic.upload <= o.max_upload_bytes);
  return all;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "bench_odometry: per-stage ms/frame and end-to-end Hz of odom_client's pipeline against a\n"
      "real map_server (spawned here, UDP multicast on loopback, random port 40000-49999), side\n"
      "by side with a --baseline odometry binary on the same data. Targets: registration <= 20\n"
      "ms/frame; end to end >= 1.2x the baseline (>= 35 Hz without one); frame time p99 <= 3x\n"
      "median; chunk traffic <= 300 KiB/frame; Integrate upload <= 1 MB/frame. Exit 1 when one\n"
      "is missed, 77 when the data is absent."};
  Options o;
  addOptions(app, o);
  CLI11_PARSE(app, argc, argv);
  if (o.smoke) o.passes = 1;
  if (!o.config_file.empty()) o.config = loadOdomConfig(o.config_file);
  if (!fs::exists(o.data)) {
    std::printf("SKIP: data folder %s not found\n", o.data.c_str());
    return 77;  // ctest SKIP_RETURN_CODE (bench/CMakeLists.txt)
  }

  Measured m;
  std::random_device rd;
  for (int pass = 0; pass < o.passes; ++pass)
    if (!runPass(o, rd(), m)) return 1;
  std::optional<double> baseline;
  if (!o.baseline.empty()) {
    baseline = baselineFps(o.baseline, o.data);
    if (!baseline) return 1;
  }

  std::printf("## odom_client pipeline on %s (%d pass(es), %zu frames measured)\n\n",
              o.data.c_str(), o.passes, m.rows.size());
  // Registration as the pipeline runs it: against the map before the frame is integrated, with
  // the real threshold, coarse-to-fine start and deskew passes.
  const double register_mean = printStages(m.rows);
  const double hz = m.wall > 0.0 ? m.frames / m.wall : 0.0;
  const Traffic traffic = printMetrics(m, hz);
  std::printf("\n| system | rate | note |\n|---|---|---|\n");
  std::printf(
      "| socc (odom_client + map_server, end to end) | %.1f Hz | files read in the loop |\n", hz);
  if (baseline)
    std::printf("| baseline (%s) | %.1f fps | as it reports (e.g. registration only) |\n",
                o.baseline.c_str(), *baseline);
  std::printf("\n");
  const bool met = judge(o, register_mean, hz, baseline, m.rows, traffic);
  if (o.smoke) std::printf("- smoke run: targets not judged\n");
  return o.smoke || met ? 0 : 1;
}
