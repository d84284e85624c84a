// bench_vendor_decoders: decoding speed of the Ouster and Hesai decoders on one core, as a
// multiple of real time (issue 28: at least 20x for a 64-beam stream). Packets are synthetic
// (tests/sensors/vendor_packets.hpp) with a return in every pixel, the worst case; thread CPU
// time, the best of 3 runs. Prints a table; exits 1 when a stream decodes slower than the target.
#include <time.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "socc/large_message_heap.hpp"
#include "socc/sensors/hesai_decoder.hpp"
#include "socc/sensors/ouster_decoder.hpp"
#include "vendor_packets.hpp"

namespace {

namespace tp = socc::sensors::test_packets;
using socc::sensors::Packet;

double threadCpuS() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
}

struct Stream {
  std::string name;
  std::vector<Packet> packets;
  double seconds = 0.0;  // of sensor time the packets cover
  socc::sensors::SensorConfig config;
  bool ouster = false;
};

Stream hesaiStream(const std::string& model, std::uint8_t mode, double seconds,
                   const std::filesystem::path& dir) {
  tp::HesaiSpec s;
  s.model = model;
  s.return_mode = mode;
  Stream st;
  st.name = model + (s.returns() == 2 ? " dual" : " single");
  st.seconds = seconds;
  st.config.model = model;
  if (model != "pandarxt32") {
    st.config.calibration = dir / (model + ".csv");
    std::ofstream(st.config.calibration) << tp::hesaiCalibrationCsv(s.lasers());
  }
  const int rounds = s.blocks() / s.returns();
  const double packet_s = rounds * s.roundPeriodUs() * 1e-6;
  const auto unit = [](int block, int laser) {
    return tp::HesaiUnit{static_cast<std::uint16_t>(2000 + 37 * laser + 300 * (block % 2)), 50};
  };
  for (int k = 0; k * packet_s < seconds; ++k) {
    const auto us = static_cast<std::int64_t>(k * packet_s * 1e6);
    Packet p;
    p.data = tp::hesaiPacket(s, (k * rounds * s.azimuthStep()) % 36000,
                             1'700'000'000 + us / 1000000, static_cast<std::uint32_t>(us % 1000000),
                             unit, static_cast<std::uint32_t>(k));
    st.packets.push_back(std::move(p));
  }
  return st;
}

Stream ousterStream(const std::string& profile, double seconds, const std::filesystem::path& dir) {
  tp::OusterSpec s;
  s.profile = profile;
  s.prod_line = "OS-1-128";
  s.beams = 128;
  s.columns_per_frame = 1024;
  s.column_period_ns = 97656;
  Stream st;
  st.name = "os1-128 " + profile;
  st.seconds = seconds;
  st.ouster = true;
  st.config.calibration = dir / (profile + ".json");
  std::ofstream(st.config.calibration) << tp::ousterMetadata(s);
  const auto pixel = [](int column, int beam) {
    return tp::OusterPixel{static_cast<std::uint32_t>(3000 + 8 * ((column + beam) % 500)), 40,
                           beam % 2 ? 0u : 20000u, 9};
  };
  const int frames = static_cast<int>(seconds * 10 + 0.5);
  for (int f = 0; f < frames; ++f)
    for (int c = 0; c < s.columns_per_frame; c += s.columns_per_packet) {
      Packet p;
      p.data = tp::ousterPacket(s, static_cast<std::uint16_t>(f), c,
                                1'000'000'000ull + static_cast<std::uint64_t>(f) * 100'000'000ull,
                                pixel);
      st.packets.push_back(std::move(p));
    }
  return st;
}

struct Result {
  double cpu_s = 0.0;
  std::size_t points = 0, scans = 0;
};

Result decodeOnce(const Stream& st) {
  auto decoder = st.ouster ? socc::sensors::makeOusterDecoder(st.config)
                           : socc::sensors::makeHesaiDecoder(st.config);
  std::vector<socc::sensors::SensorScan> scans;
  Result r;
  const double t0 = threadCpuS();
  for (const Packet& p : st.packets) {
    decoder->feed(p, scans);
    for (const auto& s : scans) r.points += s.size();
    r.scans += scans.size();
    scans.clear();  // a consumer takes every scan as it comes
  }
  r.cpu_s = threadCpuS() - t0;
  return r;
}

bool run(double seconds, double target, bool smoke) {
  const auto dir =
      std::filesystem::temp_directory_path() / ("socc_bench_vendor_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::vector<Stream> streams;
  streams.push_back(hesaiStream("pandar64", 0x37, seconds, dir));
  streams.push_back(hesaiStream("pandar64", 0x39, seconds, dir));
  streams.push_back(hesaiStream("pandar40p", 0x37, seconds, dir));
  streams.push_back(hesaiStream("pandarxt32", 0x39, seconds, dir));
  streams.push_back(ousterStream("RNG19_RFL8_SIG16_NIR16", seconds, dir));
  streams.push_back(ousterStream("RNG19_RFL8_SIG16_NIR16_DUAL", seconds, dir));
  streams.push_back(ousterStream("RNG15_RFL8_NIR8", seconds, dir));

  std::printf("%-34s %9s %12s %12s %10s %8s\n", "stream", "packets", "points/s", "CPU ms/s",
              "x realtime", "target");
  bool ok = true;
  for (const Stream& st : streams) {
    Result best;
    for (int run = 0; run < (smoke ? 1 : 3); ++run) {
      const Result r = decodeOnce(st);
      if (run == 0 || r.cpu_s < best.cpu_s) best = r;
    }
    const double factor = st.seconds / std::max(best.cpu_s, 1e-9);
    const bool met = smoke || factor >= target;
    ok = ok && met;
    std::printf("%-34s %9zu %12.0f %12.1f %10.1f %8s\n", st.name.c_str(), st.packets.size(),
                best.points / st.seconds, best.cpu_s / st.seconds * 1e3, factor,
                smoke ? "-"
                : met ? "ok"
                      : "MISSED");
  }
  std::filesystem::remove_all(dir);
  return ok;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Decoding speed of the Ouster and Hesai packet decoders on one core, as a multiple of\n"
      "real time, on synthetic packets with a return in every pixel. Exits 1 when a stream\n"
      "decodes slower than --target times real time."};
  double seconds = 2.0, target = 20.0;
  bool smoke = false;
  app.add_option("--seconds", seconds, "sensor time per stream [s]")->check(CLI::Range(0.2, 60.0));
  app.add_option("--target", target, "required multiple of real time");
  app.add_flag("--smoke", smoke, "0.3 s per stream, one run, no target judged (CI)");
  CLI11_PARSE(app, argc, argv);
  socc::keepHeapForLargeMessages();  // as socc-lidar and odom_client: sweeps are megabytes
  if (smoke) seconds = 0.3;
  try {
    return run(seconds, target, smoke) ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_vendor_decoders: %s\n", e.what());
    return 2;
  }
}
