// socc-to-lcmlog: converts a KITTI-layout directory, a directory of PCD files or a recording
// (pcap capture, ROS bag: docs/sensors.md) into an LCM log of socc::scan_t messages, to be
// replayed with lcm-logplayer (see docs/lcm.md).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <iostream>

#include "socc/channels.hpp"
#include "socc/large_message_heap.hpp"
#include "socc/rpc/client_id.hpp"
#include "socc/sensors/recording.hpp"
#include "socc/tools/recording_log_writer.hpp"
#include "socc/tools/scan_directory.hpp"
#include "socc/tools/scan_log_writer.hpp"
#include "socc/version.hpp"
#include "socc/wall_clock.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "Converts recorded scans into an LCM log of socc::scan_t messages on channel\n"
      "SOCC/SCAN/<robot-id>, replayable with lcm-logplayer.\n"
      "Input: a KITTI-layout directory (velodyne/*.bin, optional labels/*.label mapped to the\n"
      "20 classes, optional point_times/*.bin with per-point times [s]) or a directory of\n"
      "*.pcd files (x y z, optional intensity and label). Scan times come from times.txt\n"
      "(one line per frame, seconds) when present, otherwise from --rate.\n"
      "Or a recording: a pcap capture of LiDAR packets or a ROS bag (.bag, .db3, .mcap),\n"
      "decoded with --sensor / --calibration (docs/sensors.md); scans keep the recording's\n"
      "times and the sensor's per-point times."};
  app.set_version_flag("--version", socc::versionLine("socc-to-lcmlog"));
  std::string input;
  std::string output;
  socc::tools::ScanLogOptions options;
  options.start_utime = socc::nowMicros();
  bool quiet = false;
  app.add_option("input", input,
                 "KITTI sequence directory, directory of .pcd files, or a recording file")
      ->required()
      ->check(CLI::ExistingPath);
  socc::sensors::RecordingOptions recording;
  std::string calibration;
  app.add_option("--sensor", recording.sensor.model,
                 "recordings of packets: the sensor model (default: detected)");
  app.add_option("--calibration", calibration, "recordings: the sensor's calibration file")
      ->check(CLI::ExistingFile);
  app.add_option("--topic", recording.topic, "bags: the topic to read");
  app.add_option("--port", recording.port, "pcap: UDP destination port of the LiDAR data (0: any)");
  app.add_option("--sensor-address", recording.sensor.sensor_address,
                 "pcap: decode the packets of the sensor at this IPv4 address only (several "
                 "sensors on one port); default: the first sender, others are dropped and "
                 "reported");
  app.add_option("-o,--output", output, "LCM log file to write (overwritten)")->required();
  app.add_option("-r,--robot-id", options.robot_id, "robot id: channel SOCC/SCAN/<robot-id>")
      ->capture_default_str();
  app.add_option("--rate", options.rate_hz, "scan rate [Hz] when there is no times.txt")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--start-utime", options.start_utime,
                 "timestamp of the first scan [us since epoch] (default: now)");
  app.add_flag("-q,--quiet", quiet, "no progress bar");
  CLI11_PARSE(app, argc, argv);
  options.progress = !quiet;
  socc::keepHeapForLargeMessages();  // sweeps and their scan_t are megabytes each

  if (const std::string why = socc::rpc::checkClientId(options.robot_id); !why.empty()) {
    std::cerr << "socc-to-lcmlog: bad --robot-id: " << why << "\n";
    return 2;
  }
  try {
    socc::tools::ScanLogSummary s;
    if (std::filesystem::is_directory(input)) {
      s = socc::tools::writeScanLog(socc::tools::openScanDirectory(input), output, options);
    } else {
      recording.sensor.calibration = calibration;
      const std::unique_ptr<socc::sensors::ScanStream> stream =
          socc::sensors::openRecording(input, recording);
      s = socc::tools::writeRecordingLog(*stream, output, options.robot_id, options.progress);
      std::cerr << stream->problems();
    }
    std::printf("wrote %zu scans (%zu points) on %s to %s, utime %lld..%lld\n", s.scans, s.points,
                socc::channels::scan(options.robot_id).c_str(), output.c_str(),
                static_cast<long long>(s.first_utime), static_cast<long long>(s.last_utime));
  } catch (const std::exception& e) {
    std::cerr << "socc-to-lcmlog: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
