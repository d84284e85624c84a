// fuzz_seeds <dir>: writes a small seed corpus per harness into <dir>/<harness>/ — valid
// encoded requests and valid files — so the fuzzers start from inputs that reach deep code.
#include <CLI/CLI.hpp>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "bag_seeds.hpp"
#include "socc/auth/message_auth.hpp"
#include "socc/chunk_request_t.hpp"
#include "socc/integrate_request_t.hpp"
#include "socc/keyframes_request_t.hpp"
#include "socc/localize_request_t.hpp"
#include "socc/map_command_request_t.hpp"
#include "socc/part_t.hpp"
#include "socc/render_request_t.hpp"
#include "socc/robot_pose_request_t.hpp"
#include "socc/robot_status_request_t.hpp"
#include "socc/scan_t.hpp"
#include "socc/stats_request_t.hpp"
#include "socc/wire_arrays.hpp"
#include "velodyne_model_cases.hpp"
#include "vendor_packets.hpp"

namespace {
namespace fs = std::filesystem;

class SeedWriter {
 public:
  explicit SeedWriter(fs::path root) : root_(std::move(root)) {}

  void bytes(const std::string& harness, const std::string& name, const std::string& content) {
    fs::create_directories(root_ / harness);
    std::ofstream(root_ / harness / name, std::ios::binary) << content;
  }
  template <class Msg>
  void message(const std::string& harness, const std::string& name, const Msg& msg) {
    std::string buf(static_cast<std::size_t>(msg.getEncodedSize()), '\0');
    msg.encode(buf.data(), 0, static_cast<int>(buf.size()));
    bytes(harness, name, buf);
  }
  /// For the selector-byte harnesses: first byte picks the reader.
  void selected(const std::string& harness, char selector, const std::string& name,
                const std::string& content) {
    bytes(harness, name, std::string(1, selector) + content);
  }

 private:
  fs::path root_;
};

socc::request_header_t header(const std::string& service) {
  socc::request_header_t h{};
  h.request_id = 1;
  h.client_id = "robot1";
  h.reply_channel = "SOCC/" + service + "/REP/robot1";
  h.utime = 1'700'000'000'000'000;
  return h;
}

template <class T>
std::string raw(const std::vector<T>& v) {
  return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

// A 12-point labelled scan with times, plain and signed; the other seeds reuse its points.
socc::integrate_request_t integrateSeeds(SeedWriter& w) {
  const auto key = socc::auth::SharedKey::fromBytes(std::vector<std::uint8_t>(32, 7));
  socc::integrate_request_t in{};
  in.header = header("INTEGRATE");
  in.seq = 1;
  in.scan_utime = in.header.utime;
  in.sensor_pose.quaternion[0] = 1.0;
  socc::Points points;
  for (int i = 0; i < 12; ++i) {
    points.emplace_back(static_cast<float>(i) - 6.f, 3.f, 0.5f);
    in.label.push_back(static_cast<std::uint8_t>(i % 20));
    in.time.push_back(0.008f * static_cast<float>(i));
  }
  in.xyz_resolution = socc::wire::quantizePoints(points, in.xyz);
  in.num_points = in.num_labels = in.num_times = 12;
  w.message("fuzz_integrate_request", "plain", in);
  socc::integrate_request_t with_gravity = in;  // an INS's up direction (docs/lcm.md)
  with_gravity.gravity_up[0] = 0.6f;
  with_gravity.gravity_up[2] = 0.8f;
  with_gravity.gravity_sigma = 6e-4f;
  w.message("fuzz_integrate_request", "gravity", with_gravity);
  socc::auth::sign(in, key, 42);
  w.message("fuzz_integrate_request", "signed", in);
  return in;
}

void chunkSeeds(SeedWriter& w) {
  socc::chunk_request_t chunk{};
  chunk.header = header("GET_CHUNK");
  chunk.shape = socc::chunk_request_t::SHAPE_SPHERE;
  chunk.radius = 10.0;
  chunk.occupancy_threshold = 0.5f;
  chunk.fields = socc::chunk_request_t::FIELD_FEATURES | socc::chunk_request_t::FIELD_INDEX;
  w.message("fuzz_chunk_request", "sphere", chunk);
  chunk.shape = socc::chunk_request_t::SHAPE_BOX;
  for (int a = 0; a < 3; ++a) {
    chunk.box_min[a] = -10.0;
    chunk.box_max[a] = 10.0;
  }
  chunk.fields = 15;
  chunk.limit = 100;
  w.message("fuzz_chunk_request", "box_all_fields", chunk);
}

// GET_STATS, GET_ROBOT_POSE, GET_KEYFRAMES and ROBOT_STATUS (every tracking state).
void robotSeeds(SeedWriter& w, std::int64_t utime) {
  socc::stats_request_t stats{};
  stats.header = header("GET_STATS");
  w.message("fuzz_stats_request", "stats", stats);

  socc::robot_pose_request_t pose{};
  pose.header = header("GET_ROBOT_POSE");
  pose.robot_id = "seed";
  w.message("fuzz_robot_pose_request", "known", pose);
  pose.max_history = 100;
  pose.history_from_seq = 2;
  w.message("fuzz_robot_pose_request", "history", pose);

  socc::keyframes_request_t keyframes{};
  keyframes.header = header("GET_KEYFRAMES");
  keyframes.robot_id = "seed";
  keyframes.max_keyframes = 100;
  w.message("fuzz_keyframes_request", "all", keyframes);
  keyframes.from_seq = 2;
  keyframes.max_keyframes = 1;
  w.message("fuzz_keyframes_request", "page", keyframes);

  socc::robot_status_request_t status{};
  status.header = header("ROBOT_STATUS");
  status.seq = 1;
  status.utime = utime;
  for (std::int8_t state = 0; state < 4; ++state) {
    status.tracking_state = state;
    status.reason = state == 0 ? "" : "12 unhealthy frames in a row";
    w.message("fuzz_robot_status_request", "state" + std::to_string(state), status);
  }
}

// LOCALIZE: the seed ring as a scan, searched with and without a hint, and checked at a pose.
void localizeSeeds(SeedWriter& w, const socc::integrate_request_t& in) {
  socc::localize_request_t r{};
  r.header = header("LOCALIZE");
  r.num_points = in.num_points;
  socc::wire::pointsToRows(socc::wire::pointsFromQuantized(in.xyz, in.xyz_resolution), r.xyz);
  r.hint_yaw_tolerance = 3.2;
  r.max_candidates = 3;
  w.message("fuzz_localize_request", "search", r);
  r.hint_radius = 5.0;
  w.message("fuzz_localize_request", "hint", r);
  r.hint_radius = 0.0;
  r.check_pose.resize(1);
  r.check_pose[0].quaternion[0] = 1.0;
  r.num_check = 1;
  w.message("fuzz_localize_request", "check", r);
}

// MAP_COMMAND (each command) and RENDER (each mode).
void mapSeeds(SeedWriter& w) {
  socc::map_command_request_t cmd{};
  cmd.header = header("MAP_COMMAND");
  cmd.occupancy_threshold = 0.5f;
  const std::pair<std::int8_t, const char*> commands[] = {
      {socc::map_command_request_t::SAVE, "snap.socc"},
      {socc::map_command_request_t::LOAD, "snap.socc"},
      {socc::map_command_request_t::EXPORT_OCTOMAP_BT, "map.bt"},
      {socc::map_command_request_t::EXPORT_PCD, "map.pcd"},
      {socc::map_command_request_t::CLEAR, ""}};
  for (const auto& [command, path] : commands) {
    cmd.command = command;
    cmd.path = path;
    w.message("fuzz_map_command_request", "command" + std::to_string(command), cmd);
  }

  socc::render_request_t render{};
  render.header = header("RENDER");
  for (int a = 0; a < 3; ++a) {
    render.box_min[a] = -12.0;
    render.box_max[a] = 12.0;
  }
  render.pixel_size = 0.5;
  render.occupancy_threshold = 0.5f;
  for (std::int8_t mode = 0; mode < 3; ++mode) {
    render.mode = mode;
    w.message("fuzz_render_request", "mode" + std::to_string(mode), render);
  }
}

void scanSeed(SeedWriter& w, const socc::integrate_request_t& in) {
  socc::scan_t scan{};
  scan.utime = in.scan_utime;
  scan.robot_id = "robot1";
  socc::wire::pointsToRows(socc::wire::pointsFromQuantized(in.xyz, in.xyz_resolution), scan.xyz);
  scan.label = in.label;
  scan.time = in.time;
  scan.intensity.assign(12, 0.5f);
  scan.num_points = scan.num_labels = scan.num_times = scan.num_intensities = 12;
  w.message("fuzz_scan", "scan", scan);
}

// fuzz_part_assembler: records [2-byte big-endian length][part_t]; a 3-part message in order,
// the same shuffled with a duplicate, and a transfer with a part missing (it stalls).
void partSeeds(SeedWriter& w) {
  std::vector<std::string> parts;
  for (std::int32_t i = 0; i < 3; ++i) {
    socc::part_t p{};
    p.sender = "robot1.0badc0de";
    p.transfer_id = 42;
    p.index = i;
    p.count = 3;
    p.total_size = 25;
    p.offset = 10 * i;
    p.size = i < 2 ? 10 : 5;
    p.data.assign(static_cast<std::size_t>(p.size), static_cast<std::uint8_t>('a' + i));
    std::string buf(static_cast<std::size_t>(p.getEncodedSize()), '\0');
    p.encode(buf.data(), 0, static_cast<int>(buf.size()));
    parts.push_back(std::string{static_cast<char>(buf.size() >> 8), static_cast<char>(buf.size())} +
                    buf);
  }
  w.bytes("fuzz_part_assembler", "in_order", parts[0] + parts[1] + parts[2]);
  w.bytes("fuzz_part_assembler", "shuffled", parts[2] + parts[0] + parts[2] + parts[1]);
  w.bytes("fuzz_part_assembler", "missing", parts[0] + parts[2]);
}

void requestSeeds(SeedWriter& w) {
  const socc::integrate_request_t in = integrateSeeds(w);
  chunkSeeds(w);
  robotSeeds(w, in.scan_utime);
  localizeSeeds(w, in);
  mapSeeds(w);
  scanSeed(w, in);
  partSeeds(w);
}

void fileSeeds(SeedWriter& w) {
  const std::string r = "fuzz_file_readers";
  w.selected(r, 0, "kitti_bin", raw(std::vector<float>{1, 2, 3, 0.5f, 4, 5, 6, 0.25f}));
  w.selected(r, 1, "labels", raw(std::vector<std::uint32_t>{40, (3u << 16) | 10u}));
  const std::string row = "1 0 0 0.5 0 1 0 0.25 0 0 1 -1\n";
  w.selected(r, 2, "poses", row + row);
  w.selected(r, 3, "calib", "P0: 1 2 3\nTr: " + row);
  w.selected(r, 4, "tum",
             "# t x y z qx qy qz qw\n0.1 1 2 3 0 0 0 1\n0.2 1 2 3 0 0 0.7071068 0.7071068\n");
  w.selected(r, 5, "times", "0.0\n1.036e-01\n");
  w.selected(r, 6, "xyz", raw(std::vector<float>{1, 2, 3}));
  w.selected(r, 7, "floats", raw(std::vector<float>{0.0f, 0.05f}));
  w.selected(r, 8, "gravity", "0.01 -0.02 0.9997499 6.0e-04\n0 0 1 0\n");

  const std::string y = "fuzz_config_yaml";
  w.selected(y, 0, "map.yaml", "voxel_size: 0.5\nmax_range: 80\nsemantics: true\np_hit: 0.55\n");
  w.selected(y, 1, "server.yaml",
             "file_dir: /tmp\nlimits:\n  max_robots: 4\n  max_render_pixels: 1000\n");

  const std::string p = "fuzz_pcd_scan";
  const std::string head =
      "VERSION .7\nFIELDS x y z intensity label\nSIZE 4 4 4 4 4\nTYPE F F F F U\n"
      "COUNT 1 1 1 1 1\nWIDTH 2\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\n";
  w.bytes(p, "ascii.pcd", head + "DATA ascii\n1 2 3 0.5 10\n4 5 6 0.25 40\n");
  std::string body(2 * 20, '\0');
  const float pt[4] = {1, 2, 3, 0.5f};
  const std::uint32_t label = 50;
  for (int i = 0; i < 2; ++i) {
    std::memcpy(body.data() + 20 * i, pt, sizeof pt);
    std::memcpy(body.data() + 20 * i + 16, &label, sizeof label);
  }
  w.bytes(p, "binary.pcd", head + "DATA binary\n" + body);
}

// Packets with a 2-byte length each (sensor_fuzz_input.hpp) behind a selector byte.
std::string packetSeed(char selector, const std::vector<std::vector<std::uint8_t>>& packets) {
  std::string seed(1, selector);
  for (const auto& p : packets) {
    seed += static_cast<char>(p.size() & 0xff);
    seed += static_cast<char>(p.size() >> 8);
    seed.append(p.begin(), p.end());
  }
  return seed;
}

void vendorSensorSeeds(SeedWriter& w) {
  namespace tp = socc::sensors::test_packets;
  const auto unit = [](int block, int laser) {
    return tp::HesaiUnit{static_cast<std::uint16_t>(1000 + 10 * laser + block), 40};
  };
  const char* const models[] = {"pandarxt32", "pandar40p", "pandar64"};
  for (int m = 0; m < 3; ++m) {
    for (const std::uint8_t mode : {0x37, 0x39}) {
      tp::HesaiSpec spec;
      spec.model = models[m];
      spec.return_mode = mode;
      std::vector<std::vector<std::uint8_t>> packets;
      for (int k = 0; k < 3; ++k)  // across the cut at 0 deg
        packets.push_back(tp::hesaiPacket(spec, (35800 + k * 8 * spec.azimuthStep()) % 36000,
                                          1'700'000'000, static_cast<std::uint32_t>(k * 400), unit,
                                          static_cast<std::uint32_t>(k)));
      w.bytes("fuzz_hesai_decoder", std::string(models[m]) + "_" + std::to_string(mode),
              packetSeed(static_cast<char>(m | 0x40), packets));
    }
    tp::HesaiSpec spec;
    spec.model = models[m];
    w.bytes(
        "fuzz_hesai_decoder", std::string(models[m]) + "_csv",
        std::string(1, static_cast<char>(3 | (m << 2))) + tp::hesaiCalibrationCsv(spec.lasers()));
  }
  const char* const profiles[] = {"LEGACY", "RNG19_RFL8_SIG16_NIR16", "RNG15_RFL8_NIR8",
                                  "RNG19_RFL8_SIG16_NIR16_DUAL"};
  for (int p = 0; p < 4; ++p) {
    tp::OusterSpec spec;
    spec.profile = profiles[p];
    const auto pixel = [](int column, int beam) {
      return tp::OusterPixel{static_cast<std::uint32_t>(2000 + 8 * (column + beam)), 30,
                             beam % 3 ? 0u : 9000u, 5};
    };
    // The last packet of frame 3, then the first of frame 4.
    const std::vector<std::vector<std::uint8_t>> packets = {
        tp::ousterPacket(spec, 3, 512 - 16, 1'000'000'000, pixel),
        tp::ousterPacket(spec, 4, 0, 1'100'000'000, pixel)};
    w.bytes("fuzz_ouster_decoder", profiles[p], packetSeed(static_cast<char>(p | 0x40), packets));
    w.bytes("fuzz_ouster_decoder", std::string(profiles[p]) + "_json",
            std::string(1, static_cast<char>(4 + 5 * p)) + tp::ousterMetadata(spec, p % 2));
  }
}

// A VLP-16 stream of a 10 Hz turn: 12 blocks FF EE with azimuths, 32 echoes each, stamp and
// factory bytes (the VLP-16 manual's layout).
std::string vlp16Packets(int count) {
  std::string all;
  for (int k = 0; k < count; ++k) {
    std::string p(1206, '\0');
    const double stamp_us = 1e6 + k * 1327.104;
    for (int b = 0; b < 12; ++b) {
      const auto az =
          static_cast<std::uint16_t>(static_cast<long>(0.36 * (stamp_us + 110.592 * b)) % 36000);
      p[100 * b] = static_cast<char>(0xFF);
      p[100 * b + 1] = static_cast<char>(0xEE);
      p[100 * b + 2] = static_cast<char>(az & 0xFF);
      p[100 * b + 3] = static_cast<char>(az >> 8);
      for (int c = 0; c < 32; ++c) {
        const std::uint16_t raw = static_cast<std::uint16_t>(2000 + 7 * c);
        p[100 * b + 4 + 3 * c] = static_cast<char>(raw & 0xFF);
        p[100 * b + 5 + 3 * c] = static_cast<char>(raw >> 8);
        p[100 * b + 6 + 3 * c] = static_cast<char>(c * 5);
      }
    }
    const auto stamp = static_cast<std::uint32_t>(stamp_us);
    std::memcpy(p.data() + 1200, &stamp, 4);
    p[1204] = 0x37;
    p[1205] = 0x22;
    all += p;
  }
  return all;
}

// A classic pcap (little endian, microseconds, Ethernet) of UDP datagrams to port 2368.
std::string pcapOf(const std::string& packets, std::size_t packet_size) {
  std::string f;
  auto u32 = [&f](std::uint32_t v) { f.append(reinterpret_cast<const char*>(&v), 4); };
  auto u16 = [&f](std::uint16_t v) { f.append(reinterpret_cast<const char*>(&v), 2); };
  u32(0xA1B2C3D4);
  u16(2);
  u16(4);
  u32(0);
  u32(0);
  u32(65535);
  u32(1);  // Ethernet
  for (std::size_t at = 0; at + packet_size <= packets.size(); at += packet_size) {
    const std::size_t frame = 14 + 20 + 8 + packet_size;
    u32(1'700'000'000);
    u32(static_cast<std::uint32_t>(at / packet_size * 1327));
    u32(static_cast<std::uint32_t>(frame));
    u32(static_cast<std::uint32_t>(frame));
    std::string e(14, '\0');
    e[12] = 0x08;
    std::string ip(20, '\0');
    ip[0] = 0x45;
    ip[2] = static_cast<char>((20 + 8 + packet_size) >> 8);
    ip[3] = static_cast<char>((20 + 8 + packet_size) & 0xFF);
    ip[8] = 64;
    ip[9] = 17;
    std::string udp(8, '\0');
    udp[0] = 0x09, udp[1] = 0x40, udp[2] = 0x09, udp[3] = 0x40;  // 2368 -> 2368
    udp[4] = static_cast<char>((8 + packet_size) >> 8);
    udp[5] = static_cast<char>((8 + packet_size) & 0xFF);
    f += e + ip + udp + packets.substr(at, packet_size);
  }
  return f;
}

void velodyneSensorSeeds(SeedWriter& w) {
  const std::string stream = vlp16Packets(24);
  w.selected("fuzz_velodyne_decoder", 0, "vlp16", stream);
  w.selected("fuzz_velodyne_decoder", 3, "detect", stream);
  w.selected("fuzz_velodyne_decoder", 0x24, "vlp16_partial_strongest", stream);
  // Return-mode bits 3: the calibrated models (HDL-64E all / strongest / last, VLS-128).
  const auto packetsOf = [](const socc::sensors::test::ModelCase& m) {
    std::string s;
    for (const socc::sensors::Packet& p : socc::sensors::test::makePackets(m, 24, 1'000'000u))
      s.append(p.data.begin(), p.data.end());
    return s;
  };
  const std::string hdl64_dual = packetsOf(socc::sensors::test::hdl64e(true));
  w.selected("fuzz_velodyne_decoder", 0x0C, "hdl64e_dual", hdl64_dual);
  w.selected("fuzz_velodyne_decoder", 0x0D, "hdl64e_dual_strongest", hdl64_dual);
  w.selected("fuzz_velodyne_decoder", 0x0E, "hdl64e_dual_last", hdl64_dual);
  w.selected("fuzz_velodyne_decoder", 0x0C, "hdl64e",
             packetsOf(socc::sensors::test::hdl64e(false)));
  w.selected("fuzz_velodyne_decoder", 0x0F, "vls128_dual",
             packetsOf(socc::sensors::test::vls128(true)));
  w.bytes("fuzz_pcap_source", "vlp16.pcap", pcapOf(vlp16Packets(8), 1206));
  w.selected("fuzz_velodyne_calibration", 0, "veloview.xml",
             "<?xml version=\"1.0\"?>\n<boost_serialization><DB><distLSB_>0.2</distLSB_><enabled_>"
             "<count>2</count><item>1</item><item>1</item></enabled_><points_><count>2</count>"
             "<item><px><id_>0</id_><rotCorrection_>0</rotCorrection_><vertCorrection_>-15"
             "</vertCorrection_><distCorrection_>0</distCorrection_></px></item><item><px><id_>1"
             "</id_><rotCorrection_>1.4</rotCorrection_><vertCorrection_>1</vertCorrection_></px>"
             "</item></points_></DB></boost_serialization>\n");
  w.selected(
      "fuzz_velodyne_calibration", 1, "ros.yaml",
      "lasers:\n  - {laser_id: 0, rot_correction: 0.0, vert_correction: -0.26}\n"
      "  - {laser_id: 1, rot_correction: 0.02, vert_correction: 0.017, dist_correction: 0.01}\n"
      "num_lasers: 2\ndistance_resolution: 0.002\n");
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Writes a seed corpus for every socc fuzz harness into <dir>/<harness>/\n"
      "(valid encoded requests and files; used by scripts/fuzz.sh)."};
  std::string dir;
  app.add_option("dir", dir, "output directory")->required();
  CLI11_PARSE(app, argc, argv);
  try {
    SeedWriter w(dir);
    requestSeeds(w);
    fileSeeds(w);
    vendorSensorSeeds(w);
    velodyneSensorSeeds(w);
    for (const socc::fuzz::BagSeed& s : socc::fuzz::bagSeeds(dir)) {
      w.bytes(s.harness, s.name, s.content);
    }
  } catch (const std::exception& e) {
    std::cerr << "fuzz_seeds: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
