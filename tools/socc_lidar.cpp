// socc-lidar: a LiDAR driver. Decodes a live sensor's UDP packets, or replays a recording (pcap
// capture, ROS bag) at its recorded pace or as fast as possible, and publishes every sweep as a
// socc::scan_t with per-point times on SOCC/SCAN/<robot-id> (docs/sensors.md).
#include <CLI/CLI.hpp>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <lcm/lcm-cpp.hpp>
#include <thread>

#include "socc/channels.hpp"
#include "socc/large_message_heap.hpp"
#include "socc/lcm_url.hpp"
#include "socc/rpc/client_id.hpp"
#include "socc/sensors/decoded_scan_stream.hpp"
#include "socc/sensors/recording.hpp"
#include "socc/sensors/udp_source.hpp"
#include "socc/tools/sensor_scan_message.hpp"
#include "socc/version.hpp"

namespace {

// The only process-wide state: async-signal-safe stop request (Ctrl-C ends after the sweep).
std::atomic<bool> g_stop{false};
void onSignal(int) {
  g_stop = true;
}

struct Args {
  std::string pcap, bag, topic, calibration, returns = "all";
  bool live = false, keep_partial = false, quiet = false;
  socc::sensors::SensorConfig sensor;
  socc::sensors::UdpOptions udp;
  std::uint16_t pcap_port = 0;
  double rate = 1.0;
  double idle_timeout_s = 2.0;
  std::string robot_id = "robot1";
  std::string lcm_url{socc::channels::kDefaultLcmUrl};
};

void addOptions(CLI::App& app, Args& a) {
  auto* live =
      app.add_flag("--live", a.live, "receive the sensor's UDP packets (--address, --port)");
  auto* pcap = app.add_option("--pcap", a.pcap, "replay a pcap capture")->check(CLI::ExistingFile);
  auto* bag = app.add_option("--bag", a.bag, "replay a ROS bag (.bag, .db3, .mcap)")
                  ->check(CLI::ExistingPath);
  live->excludes(pcap)->excludes(bag);
  pcap->excludes(bag);
  std::string models;
  for (const std::string& m : socc::sensors::supportedModels())
    models += (models.empty() ? "" : ", ") + m;
  app.add_option("--sensor", a.sensor.model, "sensor model (" + models + "); default: detected");
  app.add_option("--calibration", a.calibration,
                 "calibration file (VeloView .xml / ROS velodyne .yaml, Ouster .json, Hesai .csv)")
      ->check(CLI::ExistingFile);
  app.add_option("--topic", a.topic, "--bag: the topic to read")->needs(bag);
  app.add_option("--sensor-address", a.sensor.sensor_address,
                 "--live / --pcap: decode the packets of the sensor at this IPv4 address only "
                 "(several sensors on one port); default: the first sender, others are dropped "
                 "and reported");
  app.add_option("--address", a.udp.address, "--live: local address to bind")
      ->capture_default_str();
  app.add_option("--port", a.udp.port, "--live: UDP port of the data packets")
      ->capture_default_str();
  app.add_option("--pcap-port", a.pcap_port, "--pcap: UDP destination port to keep (0: any)")
      ->needs(pcap);
  app.add_option("--multicast-group", a.udp.multicast_group, "--live: join this multicast group");
  app.add_option("--interface", a.udp.interface,
                 "--live: network interface (multicast join / binding)");
  app.add_option("--idle-timeout", a.idle_timeout_s,
                 "--live: stop after this many seconds without packets")
      ->capture_default_str();
  app.add_option("--rate", a.rate,
                 "replay speed: 1 = as recorded, 2 = twice as fast, 0 = as fast as possible")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  app.add_option("--cut-azimuth", a.sensor.cut_azimuth_deg,
                 "a sweep ends where the azimuth crosses this [deg]")
      ->capture_default_str();
  app.add_option("--returns", a.returns, "all, strongest, last or first (what the sensor reports)")
      ->capture_default_str()
      ->check(CLI::IsMember({"all", "strongest", "last", "first"}));
  app.add_option("--min-range", a.sensor.min_range,
                 "drop closer returns [m] (0: the model's minimum)");
  app.add_option("--max-range", a.sensor.max_range, "drop farther returns [m] (0: no limit)");
  app.add_flag("--keep-partial", a.keep_partial,
               "also publish incomplete sweeps (first / last, lost packets)");
  app.add_option("--robot-id", a.robot_id, "robot id: channel SOCC/SCAN/<robot-id>")
      ->capture_default_str();
  app.add_option("--lcm-url", a.lcm_url, "LCM URL: udpm://239.x.y.z:port?ttl=0 or memq://")
      ->capture_default_str();
  app.add_flag("-q,--quiet", a.quiet, "no line per sweep");
}

socc::sensors::ReturnMode returnMode(const std::string& r) {
  if (r == "strongest") return socc::sensors::ReturnMode::kStrongest;
  if (r == "last") return socc::sensors::ReturnMode::kLast;
  if (r == "first") return socc::sensors::ReturnMode::kFirst;
  return socc::sensors::ReturnMode::kAll;
}

std::unique_ptr<socc::sensors::ScanStream> openInput(Args& a) {
  a.sensor.calibration = a.calibration;
  a.sensor.returns = returnMode(a.returns);
  a.sensor.keep_partial = a.keep_partial;
  if (a.live) {
    a.udp.idle_timeout = std::chrono::milliseconds(static_cast<int>(a.idle_timeout_s * 1000));
    std::unique_ptr<socc::sensors::ScanDecoder> decoder = socc::sensors::makeDecoder(a.sensor);
    std::cerr << "socc-lidar: listening on udp " << a.udp.address << ":" << a.udp.port << std::endl;
    return std::make_unique<socc::sensors::DecodedScanStream>(
        socc::sensors::openUdp(a.udp), std::move(decoder), "udp :" + std::to_string(a.udp.port));
  }
  socc::sensors::RecordingOptions o;
  o.sensor = a.sensor;
  o.topic = a.topic;
  o.port = a.pcap_port;
  return socc::sensors::openRecording(a.pcap.empty() ? a.bag : a.pcap, o);
}

// Paces a replay: sweep i is published (its end - the first sweep's end) / rate after the first.
class ReplayPace {
 public:
  explicit ReplayPace(double rate) : rate_(rate) {}
  void waitFor(std::int64_t end_utime) {
    if (rate_ <= 0.0) return;
    const auto now = std::chrono::steady_clock::now();
    if (!started_) {
      started_ = true;
      first_utime_ = end_utime;
      start_ = now;
      return;
    }
    const auto due = start_ + std::chrono::microseconds(
                                  static_cast<std::int64_t>((end_utime - first_utime_) / rate_));
    if (due > now) std::this_thread::sleep_until(due);
  }

 private:
  double rate_;
  bool started_ = false;
  std::int64_t first_utime_ = 0;
  std::chrono::steady_clock::time_point start_;
};

int run(Args& a) {
  lcm::LCM lcm(a.lcm_url);
  if (!lcm.good()) throw std::runtime_error("cannot open LCM at " + a.lcm_url);
  std::unique_ptr<socc::sensors::ScanStream> stream = openInput(a);
  const std::string channel = socc::channels::scan(a.robot_id);
  ReplayPace pace(a.live ? 0.0 : a.rate);
  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);
  std::size_t scans = 0, points = 0;
  const auto t0 = std::chrono::steady_clock::now();
  while (!g_stop) {
    std::optional<socc::sensors::SensorScan> sweep = stream->next();
    if (!sweep) break;
    pace.waitFor(socc::tools::sweepEndUtime(*sweep));
    const socc::scan_t msg = socc::tools::toScanMessage(*sweep, a.robot_id);
    lcm.publish(channel, &msg);
    ++scans;
    points += sweep->size();
    if (!a.quiet)
      std::fprintf(stderr, "socc-lidar: sweep %lld: %zu points%s\n",
                   static_cast<long long>(sweep->seq), sweep->size(),
                   sweep->complete ? "" : " (incomplete)");
  }
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("published %zu sweeps (%zu points) on %s in %.2f s (%.1f Hz)\n", scans, points,
              channel.c_str(), s, s > 0 ? scans / s : 0.0);
  std::cerr << stream->problems();
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "socc-lidar: LiDAR driver. Publishes every sweep of a live sensor (UDP packets) or of a\n"
      "recording (pcap capture, ROS bag) as socc::scan_t with per-point times on\n"
      "SOCC/SCAN/<robot-id>, where odom_client --live reads them (docs/sensors.md).\n"
      "Replays keep the recorded pace (--rate 1), or run as fast as possible (--rate 0)."};
  app.set_version_flag("--version", socc::versionLine("socc-lidar"));
  Args args;
  addOptions(app, args);
  CLI11_PARSE(app, argc, argv);
  socc::keepHeapForLargeMessages();  // sweeps and their scan_t are megabytes, 10-20 a second
  if (!args.live && args.pcap.empty() && args.bag.empty()) {
    std::cerr << "socc-lidar: no input: give --live, --pcap <file> or --bag <file>\n";
    return 2;
  }
  if (const std::string why = socc::checkLcmUrl(args.lcm_url); !why.empty()) {
    std::cerr << "socc-lidar: --lcm-url " << args.lcm_url << ": " << why << "\n";
    return 2;
  }
  if (const std::string why = socc::rpc::checkClientId(args.robot_id); !why.empty()) {
    std::cerr << "socc-lidar: bad --robot-id: " << why << "\n";
    return 2;
  }
  try {
    return run(args);
  } catch (const std::exception& e) {
    std::cerr << "socc-lidar: " << e.what() << "\n";
    return 1;
  }
}
