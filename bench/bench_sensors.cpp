// bench_sensors: the speed targets of docs/sensors.md (issue 28). Decoding a 64-beam stream
// (HDL-64E, synthetic packets of the manual's layout and timing) and the real VLP-16 capture on
// one core, as a multiple of real time (thread CPU time; target >= 20x); and the live driver
// (UDP socket + decoder) receiving an HDL-64E packet stream on 127.0.0.1 at the sensor's rate
// without losing a packet. Prints a table; exits 1 on a missed target.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <thread>

#include "socc/large_message_heap.hpp"
#include "socc/sensors/decoded_scan_stream.hpp"
#include "socc/sensors/pcap_source.hpp"
#include "socc/sensors/sensor_config.hpp"
#include "socc/sensors/udp_source.hpp"

namespace {
using socc::sensors::Packet;

constexpr double kHdl64PeriodUs = 6 * 23.296;  // HDL-64E S2 timing table: 6 upper/lower pairs
constexpr double kRealTimeTarget = 20.0;

double threadCpuS() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
}

// One HDL-64E packet of a 10 Hz turn: upper (FF EE) / lower (FF DD) blocks, echoes at 5-60 m.
Packet hdl64Packet(int k) {
  Packet p;
  p.data.assign(1206, 0);
  const double stamp_us = 1e6 + k * kHdl64PeriodUs;
  for (int b = 0; b < 12; ++b) {
    const auto az =
        static_cast<std::uint16_t>(std::lround(0.36 * (stamp_us + 23.296 * (b / 2))) % 36000);
    std::uint8_t* q = p.data.data() + 100 * b;
    q[0] = 0xFF;
    q[1] = b % 2 == 0 ? 0xEE : 0xDD;
    q[2] = static_cast<std::uint8_t>(az & 0xFF);
    q[3] = static_cast<std::uint8_t>(az >> 8);
    for (int c = 0; c < 32; ++c) {
      const auto raw = static_cast<std::uint16_t>(2500 + (k * 31 + b * 7 + c * 13) % 27000);
      q[4 + 3 * c] = static_cast<std::uint8_t>(raw & 0xFF);
      q[5 + 3 * c] = static_cast<std::uint8_t>(raw >> 8);
      q[6 + 3 * c] = static_cast<std::uint8_t>(c * 7);
    }
  }
  const auto stamp = static_cast<std::uint32_t>(stamp_us);
  for (int i = 0; i < 4; ++i)
    p.data[1200 + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(stamp >> (8 * i));
  p.stamp_ns = static_cast<std::int64_t>(stamp_us * 1000.0) + 500'000;
  p.source_port = 2368;
  return p;
}

std::filesystem::path hdl64Calibration() {
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / "bench_sensors_hdl64e.yaml";
  std::ofstream out(file);
  out << "lasers:\n";
  for (int i = 0; i < 64; ++i)
    out << "  - {laser_id: " << i << ", rot_correction: " << 0.001 * (i % 5)
        << ", vert_correction: " << (-24.8 + 26.8 * i / 63.0) * M_PI / 180.0
        << ", dist_correction: 0.01, dist_correction_x: 0.012, dist_correction_y: 0.011, "
           "vert_offset_correction: 0.2, horiz_offset_correction: 0.026}\n";
  out << "num_lasers: 64\ndistance_resolution: 0.002\n";
  return file;
}

struct Row {
  std::string what;
  double value, target;
  bool higher_is_better;
  bool met() const { return higher_is_better ? value >= target : value <= target; }
};

// Decoding time of `packets` on this thread; returns the real-time multiple.
double decodeSpeed(socc::sensors::SensorConfig config, const std::vector<Packet>& packets,
                   double stream_seconds, std::size_t* points) {
  double best = 0.0;
  for (int run = 0; run < 3; ++run) {
    std::unique_ptr<socc::sensors::ScanDecoder> d = socc::sensors::makeDecoder(config);
    std::vector<socc::sensors::SensorScan> out;
    *points = 0;
    const double t0 = threadCpuS();
    for (const Packet& p : packets) {
      d->feed(p, out);
      for (const auto& s : out) *points += s.size();
      out.clear();
    }
    d->flush(out);
    const double cpu = threadCpuS() - t0;
    best = std::max(best, stream_seconds / cpu);
  }
  return best;
}

// Sends `count` HDL-64E packets to 127.0.0.1:port at the sensor's packet rate.
void sendAtSensorRate(std::uint16_t port, int count) {
  const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(port);
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  const auto start = std::chrono::steady_clock::now();
  for (int k = 0; k < count; ++k) {
    const Packet p = hdl64Packet(k);
    std::this_thread::sleep_until(
        start + std::chrono::nanoseconds(static_cast<std::int64_t>(k * kHdl64PeriodUs * 1000)));
    ::sendto(fd, p.data.data(), p.data.size(), 0, reinterpret_cast<const sockaddr*>(&to),
             sizeof to);
  }
  ::close(fd);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "bench_sensors: LiDAR decoding speed (>= 20x real time, one core) and live reception of an "
      "HDL-64E packet rate on 127.0.0.1 without loss (docs/sensors.md)."};
  double seconds = 2.0;
  std::string vlp16_pcap =
      std::string(SOCC_SHARED_DATA_DIR) +
      "/raw_sensors/01_velodyne_vlp16_veloview/vlp-16-test-90deg-1-50-frames.pcap";
  std::uint16_t port = 23680;
  app.add_option("--seconds", seconds, "length of the synthetic HDL-64E stream [s]")
      ->capture_default_str();
  app.add_option("--port", port, "loopback UDP port of the live test")->capture_default_str();
  app.add_option("--vlp16-pcap", vlp16_pcap, "the real VLP-16 capture (skipped when absent)");
  CLI11_PARSE(app, argc, argv);
  socc::keepHeapForLargeMessages();  // as socc-lidar and odom_client: sweeps are megabytes

  std::vector<Row> rows;
  // 1. HDL-64E decoding.
  const int count = static_cast<int>(seconds * 1e6 / kHdl64PeriodUs);
  std::vector<Packet> packets;
  for (int k = 0; k < count; ++k) packets.push_back(hdl64Packet(k));
  socc::sensors::SensorConfig hdl64;
  hdl64.model = "hdl64e";
  hdl64.calibration = hdl64Calibration();
  std::size_t points = 0;
  const double x64 = decodeSpeed(hdl64, packets, count * kHdl64PeriodUs * 1e-6, &points);
  std::printf("HDL-64E: %d packets (%.2f s of data), %zu points\n", count,
              count * kHdl64PeriodUs * 1e-6, points);
  rows.push_back({"HDL-64E decoding [x real time, 1 core]", x64, kRealTimeTarget, true});

  // 2. The real VLP-16 capture (packets read first: decoding only).
  if (std::filesystem::exists(vlp16_pcap)) {
    std::unique_ptr<socc::sensors::PacketSource> src = socc::sensors::openPcap(vlp16_pcap, 2368);
    std::vector<Packet> vlp;
    while (std::optional<Packet> p = src->next()) vlp.push_back(std::move(*p));
    socc::sensors::SensorConfig c;
    c.model = "vlp16";
    const double span = static_cast<double>(vlp.back().stamp_ns - vlp.front().stamp_ns) * 1e-9;
    rows.push_back({"VLP-16 capture decoding [x real time, 1 core]",
                    decodeSpeed(c, vlp, span, &points), kRealTimeTarget, true});
  }

  // 3. Live: an HDL-64E packet rate through the UDP source and the decoder.
  socc::sensors::UdpOptions udp;
  udp.address = "127.0.0.1";
  udp.port = port;
  udp.idle_timeout = std::chrono::milliseconds(500);
  auto stream = std::make_unique<socc::sensors::DecodedScanStream>(
      socc::sensors::openUdp(udp), socc::sensors::makeDecoder(hdl64), "udp");
  std::thread sender(sendAtSensorRate, port, count);
  std::size_t sweeps = 0;
  while (stream->next()) ++sweeps;
  sender.join();
  const socc::sensors::DecodeStats& st = stream->decoder().stats();
  const double lost =
      static_cast<double>(count) -
      static_cast<double>(st.packets + st.other_sender + st.foreign + st.malformed + st.late);
  std::printf("live: %d packets sent at %.0f packets/s, %llu decoded, %zu sweeps\n", count,
              1e6 / kHdl64PeriodUs, static_cast<unsigned long long>(st.packets), sweeps);
  rows.push_back({"live HDL-64E rate on 127.0.0.1: packets lost", lost, 0.0, false});

  bool ok = true;
  std::printf("\n| measure | value | target | met |\n|---|---|---|---|\n");
  for (const Row& r : rows) {
    std::printf("| %s | %.1f | %s %.0f | %s |\n", r.what.c_str(), r.value,
                r.higher_is_better ? ">=" : "<=", r.target, r.met() ? "yes" : "NO");
    ok = ok && r.met();
  }
  return ok ? 0 : 1;
}
