// bench_lcm_codec: the LCM codec table of docs/lcm.md ("Arrays are column-major"): encode,
// fresh decode (a new message, as safeDecode does) and decode into a reused message, of an
// integrate request the size of a KITTI scan and of two chunk replies, plus the client's and
// the server's whole conversion. Thread CPU time, median over batches of the mean per call.
// It judges no target (the table documents costs), so it exits 0 unless it fails to run.
#include <malloc.h>
#include <time.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "socc/chunk_reply_t.hpp"
#include "socc/integrate_request_t.hpp"
#include "socc/labels.hpp"
#include "socc/large_message_heap.hpp"
#include "socc/rpc/map_client.hpp"
#include "socc/rpc/safe_decode.hpp"
#include "socc/wire_arrays.hpp"

namespace {

struct Repeats {
  int batches = 5, runs = 31;
};

volatile std::size_t g_sink = 0;  // keeps timed results alive

double threadCpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) * 1e-6;
}

template <typename F>
double medianMs(const Repeats& r, F&& call) {
  std::vector<double> per_call;
  for (int b = 0; b < r.batches; ++b) {
    const double t0 = threadCpuMs();
    for (int i = 0; i < r.runs; ++i) call();
    per_call.push_back((threadCpuMs() - t0) / r.runs);
  }
  std::nth_element(per_call.begin(), per_call.begin() + per_call.size() / 2, per_call.end());
  return per_call[per_call.size() / 2];
}

template <typename Message>
std::vector<std::uint8_t> encodeBytes(const Message& m) {
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

// A KITTI-sized labelled scan: 122 476 points (KITTI 00 frame 0) on a 5-80 m shell.
socc::LabeledCloud syntheticScan(std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), range(5.0f, 80.0f);
  socc::LabeledCloud cloud;
  for (int i = 0; i < 122476; ++i) {
    const Eigen::Vector3f d = Eigen::Vector3f(u(rng), u(rng), 0.2f * u(rng)).normalized();
    cloud.points.push_back(range(rng) * d);
    cloud.labels.push_back(static_cast<std::uint8_t>(i % socc::kNumClasses));
  }
  return cloud;
}

template <typename T, typename Gen>
void fillRows(std::vector<std::vector<T>>& rows, int count, int n, Gen&& value) {
  rows.assign(static_cast<std::size_t>(count), std::vector<T>(static_cast<std::size_t>(n)));
  for (auto& row : rows)
    for (auto& v : row) v = static_cast<T>(value());
}

socc::chunk_reply_t syntheticChunk(int n, bool stats, std::mt19937& rng) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const auto value = [&] { return u(rng); };
  socc::chunk_reply_t c{};
  c.voxel_size = 0.5;
  c.num_voxels = c.n_features = n;
  c.fields = socc::chunk_request_t::FIELD_FEATURES;
  fillRows(c.first_point, 3, n, [&] { return 65535.0f * u(rng) - 32768.0f; });
  fillRows(c.normal, 2, n, [&] { return 32767.0f * u(rng); });
  c.planarity.assign(static_cast<std::size_t>(n), 76);  // tau 0.1
  c.occupancy.assign(static_cast<std::size_t>(n), 200);
  c.label.assign(static_cast<std::size_t>(n), socc::kRoad);
  c.label_prob.assign(static_cast<std::size_t>(n), 230);
  if (!stats) return c;
  c.fields |= socc::chunk_request_t::FIELD_STATS;
  c.n_stats = n;
  c.num_classes = socc::kNumClasses;
  fillRows(c.mean, 3, n, value);
  fillRows(c.covariance, 6, n, value);
  c.count.assign(static_cast<std::size_t>(n), 12);
  c.log_odds.assign(static_cast<std::size_t>(n), 2.0f);
  fillRows(c.class_prob, c.num_classes, n, value);
  return c;
}

struct Row {
  std::string name;
  std::size_t bytes = 0;
  double encode = NAN, decode = NAN, codec = NAN;  // [ms]; NaN: not measured on this path
};

template <typename Message>
Row messageRow(const std::string& name, const Message& m, const Repeats& r) {
  Row row{name, encodeBytes(m).size()};
  row.encode = medianMs(r, [&] { g_sink = g_sink + encodeBytes(m).size(); });
  const std::vector<std::uint8_t> bytes = encodeBytes(m);
  const int size = static_cast<int>(bytes.size());
  row.decode = medianMs(
      r, [&] { g_sink = g_sink + (socc::rpc::safeDecode<Message>(bytes.data(), size) ? 1 : 0); });
  Message reused;
  row.codec = medianMs(r, [&] { g_sink = g_sink + reused.decode(bytes.data(), 0, size); });
  return row;
}

// The client's path (cloud -> request -> bytes) and the server's (bytes -> request -> cloud).
std::vector<Row> pathRows(const socc::LabeledCloud& cloud, const Repeats& r) {
  const auto request = [&] {
    return socc::rpc::makeIntegrateRequest(1, 100000, Eigen::Isometry3d::Identity(), cloud);
  };
  Row client{"client: cloud -> request -> bytes", encodeBytes(request()).size()};
  client.encode = medianMs(r, [&] { g_sink = g_sink + encodeBytes(request()).size(); });
  const std::vector<std::uint8_t> bytes = encodeBytes(request());
  Row server{"server: bytes -> request -> cloud", bytes.size()};
  server.decode = medianMs(r, [&] {
    const auto m = socc::rpc::safeDecode<socc::integrate_request_t>(bytes.data(),
                                                                    static_cast<int>(bytes.size()));
    socc::LabeledCloud back;
    back.points = socc::wire::pointsFromQuantized(m->xyz, m->xyz_resolution);
    back.labels = m->label;
    g_sink = g_sink + back.size();
  });
  return {client, server};
}

std::string cell(double ms) {
  if (std::isnan(ms)) return "";
  char text[32];
  std::snprintf(text, sizeof(text), "%.2f ms", ms);
  return text;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "bench_lcm_codec: LCM encode/decode cost of socc's large messages (docs/lcm.md table); "
      "prints one markdown table, judges no target"};
  bool smoke = false, keep_heap = false, return_heap = false;
  Repeats r;
  app.add_flag("--smoke", smoke, "one batch of 2 runs (CI: checks that it runs)");
  auto* keep = app.add_flag(
      "--keep-heap", keep_heap,
      "keep freed memory like map_server/odom_client do (socc::keepHeapForLargeMessages)");
  app.add_flag("--return-heap", return_heap,
               "give every large buffer back to the kernel when freed (glibc's mmap threshold "
               "fixed at its 128 KiB default): each fresh decode pays its page faults again")
      ->excludes(keep);
  app.add_option("--batches", r.batches, "batches (median over them)")->capture_default_str();
  app.add_option("--runs", r.runs, "calls per batch")->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  if (smoke) r = Repeats{1, 2};
  if (keep_heap) socc::keepHeapForLargeMessages();
  if (return_heap) mallopt(M_MMAP_THRESHOLD, 128 * 1024);  // a fixed threshold never grows
  std::mt19937 rng(7);
  const socc::LabeledCloud scan = syntheticScan(rng);
  std::vector<Row> rows{
      messageRow("integrate_request_t, 122 476 points + labels",
                 socc::rpc::makeIntegrateRequest(1, 100000, Eigen::Isometry3d::Identity(), scan),
                 r),
      messageRow("chunk_reply_t, 50 000 voxels, FEATURES + STATS", syntheticChunk(50000, true, rng),
                 r),
      messageRow("chunk_reply_t, 18 800 voxels, FEATURES", syntheticChunk(18800, false, rng), r)};
  for (Row& row : pathRows(scan, r)) rows.push_back(row);
  std::printf("| message / path | bytes | encode | decode (fresh) | codec (reused) |\n");
  std::printf("|---|---|---|---|---|\n");
  for (const Row& row : rows)
    std::printf("| %s | %.2f MB | %s | %s | %s |\n", row.name.c_str(), row.bytes * 1e-6,
                cell(row.encode).c_str(), cell(row.decode).c_str(), cell(row.codec).c_str());
  return 0;
}
