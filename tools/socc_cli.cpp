// socc-cli: command-line client of map_server (stats, poses, snapshots, exports, chunks,
// rendering, test integrations). Exit code 0 on OK, 1 on an error reply or timeout.
#include <openssl/evp.h>

#include <CLI/CLI.hpp>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "socc/channels.hpp"
#include "socc/kitti_io.hpp"
#include "socc/labels.hpp"
#include "socc/pose_conversion.hpp"
#include "socc/pose_history.hpp"
#include "socc/rgb_image.hpp"
#include "socc/rpc/map_client.hpp"
#include "socc/tools/map_picture.hpp"
#include "socc/version.hpp"

namespace {

namespace fs = std::filesystem;
using socc::rpc::MapClient;

template <typename Reply>
bool report(const socc::rpc::Result<Reply>& result, const std::string& what) {
  if (result.ok()) return true;
  std::cerr << "socc-cli " << what << ": "
            << (result.error.timed_out ? "TIMEOUT" : socc::rpc::statusName(result.error.status))
            << ": " << result.error.message << '\n';
  return false;
}

// SHA-256 of a chunk's content: the reply with the per-call header and map_version blanked,
// so answers of two servers holding the same voxels compare equal byte for byte.
std::string contentDigest(socc::chunk_reply_t reply) {
  reply.header = socc::reply_header_t{};
  reply.map_version = 0;
  reply.map_epoch = 0;  // random per map instance
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(reply.getEncodedSize()));
  reply.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  std::array<unsigned char, EVP_MAX_MD_SIZE> md{};
  unsigned int length = 0;
  EVP_Digest(bytes.data(), bytes.size(), md.data(), &length, EVP_sha256(), nullptr);
  std::string hex;
  char buf[3];
  for (unsigned int i = 0; i < length; ++i) {
    std::snprintf(buf, sizeof(buf), "%02x", md[i]);
    hex += buf;
  }
  return hex;
}

// A deterministic test scene around the sensor: road-labelled ground and building walls.
socc::LabeledCloud syntheticCloud(std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-15.0f, 15.0f);
  socc::LabeledCloud cloud;
  for (int i = 0; i < 3000; ++i) {
    cloud.points.emplace_back(u(rng), u(rng), -1.7f);
    cloud.labels.push_back(socc::kRoad);
  }
  for (int i = 0; i < 3000; ++i) {
    const float along = u(rng), height = 0.2f * std::abs(u(rng)) - 1.5f;
    const bool x_wall = (i % 2) == 0;
    const float side = (i % 4) < 2 ? 16.0f : -16.0f;
    cloud.points.emplace_back(x_wall ? side : along, x_wall ? along : side, height);
    cloud.labels.push_back(socc::kBuilding);
  }
  return cloud;
}

std::int32_t parseFields(const std::vector<std::string>& names) {
  std::int32_t fields = 0;
  for (const auto& n : names) {
    if (n == "features") fields |= socc::chunk_request_t::FIELD_FEATURES;
    if (n == "stats") fields |= socc::chunk_request_t::FIELD_STATS;
    if (n == "free") fields |= socc::chunk_request_t::FIELD_FREE;
    if (n == "index") fields |= socc::chunk_request_t::FIELD_INDEX;
    if (n == "moments") fields |= socc::chunk_request_t::FIELD_MOMENTS;
  }
  return fields;
}

// Pages through a robot's pose history (GET_ROBOT_POSE with max_history) until it is complete.
bool fetchHistory(MapClient& client, const std::string& robot, socc::Poses& poses,
                  std::vector<double>& stamps) {
  std::int64_t from_seq = 0;
  for (;;) {
    // As many as the server sends in one reply (it caps the page and sets history_truncated).
    const auto r = client.getRobotPose(robot, std::numeric_limits<std::int32_t>::max(), from_seq);
    if (!report(r, "pose --history")) return false;
    const socc::pose_history_t& h = r.reply->history;
    for (std::int32_t i = 0; i < h.num_poses; ++i) {
      poses.push_back(socc::fromLcm(socc::poseAt(h, static_cast<std::size_t>(i))));
      stamps.push_back(static_cast<double>(h.scan_utime[i]) * 1e-6);
    }
    if (!r.reply->history_truncated || h.num_poses == 0) return true;
    from_seq = h.seq.back() + 1;
  }
}

void printPose(const socc::robot_state_t& s) {
  const auto& t = s.last_pose.translation;
  const auto& q = s.last_pose.quaternion;
  std::cout << s.robot_id << " seq=" << s.last_seq << " integrations=" << s.integrations
            << " utime=" << s.last_scan_utime << " t=[" << t[0] << ' ' << t[1] << ' ' << t[2]
            << "] q=[" << q[0] << ' ' << q[1] << ' ' << q[2] << ' ' << q[3]
            << "] tracking=" << socc::rpc::trackingStateName(s.tracking_state)
            << " refused=" << s.refused_integrations;
  if (s.tracking_utime != 0 || !s.tracking_reason.empty())
    std::cout << " reported_at_seq=" << s.tracking_seq << " reason=\"" << s.tracking_reason << '"';
  std::cout << '\n';
}

// socc-cli tracking STATE: ROBOT_STATUS, this client's robot reports its tracking state.
struct TrackingCommand {
  CLI::App* command = nullptr;
  std::string state;
  std::string reason;
  std::int64_t seq = 0;
  std::int64_t utime = 0;

  void add(CLI::App& app) {
    command = app.add_subcommand("tracking",
                                 "report this client's (robot's) tracking state; LOST and "
                                 "RELOCALIZING make the server refuse its integrations until it "
                                 "reports TRACKING");
    std::vector<std::string> names;
    for (std::int8_t s = 0; s <= socc::robot_status_request_t::RELOCALIZING; ++s)
      names.push_back(socc::rpc::trackingStateName(s));
    command->add_option("state", state)->required()->check(CLI::IsMember(names));
    command->add_option("--reason", reason, "why, for people (<= 200 bytes)");
    command->add_option("--seq", seq, "the frame the state refers to")->capture_default_str();
    command->add_option("--utime", utime, "that frame's time [us]")->capture_default_str();
  }

  bool run(MapClient& client) const {
    std::int8_t code = 0;
    while (socc::rpc::trackingStateName(code) != state) ++code;  // a checked name
    const auto r = client.reportTracking(code, reason, seq, utime);
    if (!report(r, "tracking")) return false;
    printPose(r.reply->state);
    return true;
  }
};

// Positions of a KITTI pose file; GT is moved so its first pose is the estimate's first pose
// (both start where the robot started), from the camera frame first when a calib is given.
std::vector<Eigen::Vector2d> trackXy(const std::string& file, const std::string& calib,
                                     const socc::Poses* align_to) {
  socc::Poses poses = socc::readKittiPoses(file);
  if (!calib.empty()) poses = socc::cameraToLidarPoses(poses, socc::readKittiCalibTr(calib));
  const Eigen::Isometry3d shift = align_to != nullptr && !align_to->empty() && !poses.empty()
                                      ? align_to->front() * poses.front().inverse()
                                      : Eigen::Isometry3d::Identity();
  std::vector<Eigen::Vector2d> xy;
  for (const auto& p : poses) xy.push_back((shift * p).translation().head<2>());
  return xy;
}

// socc-cli render: the server draws the raster (RENDER), this client decorates it.
struct RenderCommand {
  CLI::App* command = nullptr;
  std::vector<double> box;
  std::string out = "map.png", gt, gt_calib, title;
  std::vector<std::string> trajectories;
  double pixel_size = 0.0;
  int mode = 0;
  bool plain = false;

  void add(CLI::App& app) {
    command = app.add_subcommand(
        "render",
        "top-down PNG of a box, with a title, a legend of the classes present (mode 0) or an "
        "occupancy colour bar (mode 1), a scale bar and trajectories");
    command->add_option("--box", box, "xmin ymin zmin xmax ymax zmax [m]")->expected(6)->required();
    command->add_option("--out", out, "PNG file")->capture_default_str();
    command->add_option("--pixel-size", pixel_size,
                        "[m] (default: the box's long side in " +
                            std::to_string(socc::tools::kMapLongSidePixels) + " pixels)");
    command->add_option("--mode", mode, "0 class, 1 occupancy probability, 2 height")
        ->check(CLI::Range(0, 2))
        ->capture_default_str();
    command
        ->add_option("--trajectory", trajectories,
                     "estimated poses (KITTI, map frame) to draw; repeat it for several robots "
                     "(then named by their file's directory)")
        ->check(CLI::ExistingFile);
    command
        ->add_option("--gt", gt,
                     "ground-truth poses (KITTI) to draw, moved to start at the first pose "
                     "of the first --trajectory")
        ->check(CLI::ExistingFile);
    command->add_option("--gt-calib", gt_calib, "KITTI calib.txt: --gt is in the camera frame")
        ->check(CLI::ExistingFile);
    command->add_option("--title", title, "title line (default: the mode)");
    command->add_flag("--plain", plain, "write the server's raster without any decoration");
  }

  socc::tools::PictureSpec spec(double pixel) const {
    socc::tools::PictureSpec s;
    s.mode = mode;
    s.x_min = box[0];
    s.y_min = box[1];
    s.pixel_size = pixel;
    s.title = !title.empty() ? title
              : mode == 0    ? "socc map: classes"
              : mode == 1    ? "socc map: occupancy"
                             : "socc map: height";
    const socc::Poses est =
        trajectories.empty() ? socc::Poses{} : socc::readKittiPoses(trajectories.front());
    if (!gt.empty())
      s.tracks.push_back({"ground truth", {255, 255, 255}, trackXy(gt, gt_calib, &est), 3.4});
    constexpr std::array<socc::Rgb, 4> kColors{
        {{0, 225, 255}, {255, 255, 0}, {255, 120, 0}, {150, 255, 150}}};
    for (std::size_t i = 0; i < trajectories.size(); ++i) {
      const std::string dir = fs::path(trajectories[i]).parent_path().filename().string();
      s.tracks.push_back({trajectories.size() == 1 || dir.empty() ? "estimate" : dir,
                          kColors[i % kColors.size()], trackXy(trajectories[i], "", nullptr)});
    }
    return s;
  }

  bool run(MapClient& client) const {
    socc::render_request_t request{};
    for (int i = 0; i < 3; ++i) {
      request.box_min[i] = box[i];
      request.box_max[i] = box[i + 3];
    }
    request.pixel_size = pixel_size > 0.0
                             ? pixel_size
                             : socc::tools::autoPixelSize(box[3] - box[0], box[4] - box[1]);
    request.mode = static_cast<std::int8_t>(mode);
    request.occupancy_threshold = 0.5f;
    const auto r = client.render(request);
    if (!report(r, "render")) return false;
    std::vector<std::uint8_t> png = r.reply->png;
    if (!plain)
      png =
          socc::encodePng(socc::tools::decorateMap(socc::decodePng(png), spec(request.pixel_size)));
    std::ofstream file(out, std::ios::binary);
    file.write(reinterpret_cast<const char*>(png.data()), static_cast<std::streamsize>(png.size()));
    if (!file) throw std::runtime_error("cannot write " + out);
    std::cout << out << ' ' << r.reply->width << 'x' << r.reply->height << " map pixels\n";
    return true;
  }
};
// socc-cli stats: map statistics and every robot's state.
struct StatsCommand {
  CLI::App* command = nullptr;

  void add(CLI::App& app) {
    command = app.add_subcommand("stats", "print map statistics and robot states");
  }

  bool run(MapClient& client) const {
    const auto r = client.getStats();
    if (!report(r, "stats")) return false;
    const auto& s = r.reply->stats;
    std::cout << "server=" << s.server_version << " voxels=" << s.num_voxels
              << " occupied=" << s.num_occupied << " free=" << s.num_free
              << " blocks=" << s.num_blocks << " memory_bytes=" << s.memory_bytes
              << " version=" << s.map_version << " integrations=" << s.integrations
              << " rate=" << s.integrations_per_s << "/s requests=" << s.requests
              << " rejected=" << s.rejected_requests << " auth_failures=" << s.auth_failures
              << " robots=" << s.num_robots << '\n';
    for (const auto& state : s.robots) printPose(state);
    return true;
  }
};

// socc-cli pose ROBOT: the last pose the server holds, optionally the whole history.
struct PoseCommand {
  CLI::App* command = nullptr;
  std::string robot, history_kitti, history_tum;

  void add(CLI::App& app) {
    command = app.add_subcommand("pose", "print the last pose the server holds for a robot");
    command->add_option("robot", robot, "robot id")->required();
    command->add_option("--history", history_kitti,
                        "also fetch the robot's whole pose history (one pose per applied "
                        "INTEGRATE, seq order) and write it here as KITTI poses (3x4 per line)");
    command->add_option("--history-tum", history_tum,
                        "the same as TUM (scan time [s] tx ty tz qx qy qz qw)");
  }

  bool run(MapClient& client) const {
    const auto r = client.getRobotPose(robot);
    if (!report(r, "pose")) return false;
    printPose(r.reply->state);
    if (history_kitti.empty() && history_tum.empty()) return true;
    socc::Poses poses;
    std::vector<double> stamps;
    if (!fetchHistory(client, robot, poses, stamps)) return false;
    if (!history_kitti.empty()) socc::writeKittiPoses(history_kitti, poses);
    if (!history_tum.empty()) socc::writeTumPoses(history_tum, poses, stamps);
    std::cout << "history: " << poses.size() << " poses\n";
    return true;
  }
};

// socc-cli keyframes ROBOT: GET_KEYFRAMES, the robot's keyframes as the server's consistency
// service holds them now (optimized, map frame; docs/consistency.md "The revised trajectory").
struct KeyframesCommand {
  CLI::App* command = nullptr;
  std::string robot, kitti, tum;

  void add(CLI::App& app) {
    command = app.add_subcommand(
        "keyframes",
        "print how many keyframes of a robot the consistency service (map_server --consistency) "
        "holds, optionally write their optimized map-frame poses");
    command->add_option("robot", robot, "robot id")->required();
    command->add_option("--kitti", kitti, "write the poses here as KITTI (3x4 per line)");
    command->add_option("--tum", tum,
                        "write them here as TUM (scan time [s] tx ty tz qx qy qz qw)");
  }

  bool run(MapClient& client) const {
    socc::Poses poses;
    std::vector<double> stamps;
    std::int64_t from_seq = 0, first = 0, last = 0;
    for (;;) {
      const auto r = client.getKeyframes(robot, from_seq);
      if (!report(r, "keyframes")) return false;
      const socc::pose_history_t& h = r.reply->keyframes;
      for (std::int32_t i = 0; i < h.num_poses; ++i) {
        poses.push_back(socc::fromLcm(socc::poseAt(h, static_cast<std::size_t>(i))));
        stamps.push_back(static_cast<double>(h.scan_utime[i]) * 1e-6);
      }
      if (h.num_poses > 0 && from_seq == 0) first = h.seq.front();
      if (h.num_poses > 0) last = h.seq.back();
      if (!r.reply->truncated || h.num_poses == 0) {
        std::cout << robot << ": " << poses.size() << " keyframes (seq " << first << " to " << last
                  << "), " << r.reply->optimizations << " optimizations, " << r.reply->pending
                  << " keyframes waiting for the service\n";
        break;
      }
      from_seq = h.seq.back() + 1;
    }
    if (!kitti.empty()) socc::writeKittiPoses(kitti, poses);
    if (!tum.empty()) socc::writeTumPoses(tum, poses, stamps);
    return true;
  }
};

// socc-cli save|load|export|clear: MAP_COMMAND (paths are on the server).
struct MapCommand {
  CLI::App *save = nullptr, *load = nullptr, *exp = nullptr, *clear = nullptr;
  std::string path, format;
  float threshold = 0.5f;

  void add(CLI::App& app) {
    save = app.add_subcommand("save", "save a snapshot (path on the server)");
    save->add_option("path", path)->required();
    load = app.add_subcommand("load", "load a snapshot (path on the server)");
    load->add_option("path", path)->required();
    exp = app.add_subcommand("export", "export occupied voxels (OctoMap .bt/.ot or PCD)");
    exp->add_option("format", format)->required()->check(CLI::IsMember({"bt", "ot", "pcd"}));
    exp->add_option("path", path)->required();
    exp->add_option("--threshold", threshold, "occupancy threshold")->capture_default_str();
    clear = app.add_subcommand("clear", "clear the map and robot states");
  }

  bool parsed() const {
    return save->parsed() || load->parsed() || exp->parsed() || clear->parsed();
  }

  bool run(MapClient& client) const {
    socc::map_command_request_t request{};
    request.path = path;
    request.occupancy_threshold = threshold;
    using C = socc::map_command_request_t;
    if (save->parsed()) request.command = C::SAVE;
    if (load->parsed()) request.command = C::LOAD;
    if (clear->parsed()) request.command = C::CLEAR;
    if (exp->parsed())
      request.command = format == "bt"   ? C::EXPORT_OCTOMAP_BT
                        : format == "ot" ? C::EXPORT_OCTOMAP_OT
                                         : C::EXPORT_PCD;
    const auto r = client.command(request);
    if (!report(r, "command")) return false;
    std::cout << r.reply->detail << " voxels=" << r.reply->num_voxels
              << " bytes=" << r.reply->num_bytes << '\n';
    return true;
  }
};

// socc-cli chunk: GET_CHUNK of a sphere or a box; counts, bytes and optionally a digest.
struct ChunkCommand {
  CLI::App* command = nullptr;
  std::vector<double> box, sphere;
  std::vector<std::string> field_names{"features"};
  int limit = 0;
  float threshold = 0.5f;
  bool digest = false;

  void add(CLI::App& app) {
    command = app.add_subcommand("chunk", "fetch a chunk; prints counts and bytes");
    auto* sphere_opt = command->add_option("--sphere", sphere, "x y z r")->expected(4);
    command->add_option("--box", box, "xmin ymin zmin xmax ymax zmax")
        ->expected(6)
        ->excludes(sphere_opt);
    command->add_option("--fields", field_names, "features stats free index moments")
        ->check(CLI::IsMember({"features", "stats", "free", "index", "moments"}))
        ->capture_default_str();
    command->add_option("--limit", limit, "max voxels (0 = server max)");
    command->add_option("--threshold", threshold, "occupancy threshold")->capture_default_str();
    command->add_flag("--digest", digest, "also print a SHA-256 of the voxel content");
  }

  // The request, or nullopt when neither --sphere nor --box was given.
  std::optional<socc::chunk_request_t> request() const {
    socc::chunk_request_t r = socc::rpc::sphereChunkRequest(Eigen::Vector3d::Zero(), 0.0);
    if (sphere.size() == 4) {
      r = socc::rpc::sphereChunkRequest({sphere[0], sphere[1], sphere[2]}, sphere[3]);
    } else if (box.size() == 6) {
      r.shape = socc::chunk_request_t::SHAPE_BOX;
      for (int i = 0; i < 3; ++i) {
        r.box_min[i] = box[i];
        r.box_max[i] = box[i + 3];
      }
    } else {
      return std::nullopt;
    }
    r.fields = parseFields(field_names);
    r.limit = limit;
    r.occupancy_threshold = threshold;
    return r;
  }

  int run(MapClient& client) const {
    const std::optional<socc::chunk_request_t> req = request();
    if (!req) {
      std::cerr << "socc-cli chunk: give --sphere x y z r or --box ...\n";
      return 2;
    }
    const auto r = client.getChunk(*req);
    if (!report(r, "chunk")) return 1;
    std::cout << "voxels=" << r.reply->num_voxels << " free=" << r.reply->n_free
              << " truncated=" << (r.reply->truncated ? 1 : 0) << " bytes=" << r.bytes_received
              << " version=" << r.reply->map_version << '\n';
    if (digest) std::cout << "digest=" << contentDigest(*r.reply) << '\n';
    return 0;
  }
};

// socc-cli integrate: one scan (synthetic, or a KITTI .bin with labels) at a given pose.
struct IntegrateCommand {
  CLI::App* command = nullptr;
  std::int64_t seq = 0;
  std::vector<double> xyz_yaw{0, 0, 0, 0};
  std::string bin_file, label_file;
  std::uint32_t seed = 1;

  void add(CLI::App& app) {
    command = app.add_subcommand("integrate", "integrate one scan (synthetic or KITTI .bin)");
    command->add_option("--seq", seq, "per-robot sequence number")->required();
    command->add_option("--pose", xyz_yaw, "sensor x y z yaw[deg]")->expected(4);
    command->add_option("--bin", bin_file, "KITTI velodyne .bin (default: synthetic scene)")
        ->check(CLI::ExistingFile);
    command->add_option("--labels", label_file, "SemanticKITTI .label for --bin")
        ->check(CLI::ExistingFile);
    command->add_option("--seed", seed, "seed of the synthetic scene")->capture_default_str();
  }

  socc::LabeledCloud cloud() const {
    if (bin_file.empty()) return syntheticCloud(seed);
    socc::LabeledCloud c;
    c.points = socc::readKittiBin(bin_file);
    if (!label_file.empty())
      for (const std::uint32_t raw : socc::readSemanticKittiLabels(label_file))
        c.labels.push_back(socc::mapSemanticKittiLabel(raw));
    return c;
  }

  bool run(MapClient& client) const {
    Eigen::Isometry3d sensor = Eigen::Isometry3d::Identity();
    sensor.translation() = Eigen::Vector3d(xyz_yaw[0], xyz_yaw[1], xyz_yaw[2]);
    sensor.linear() =
        Eigen::AngleAxisd(xyz_yaw[3] * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    const auto r =
        client.integrate(socc::rpc::makeIntegrateRequest(seq, seq * 100000, sensor, cloud()));
    if (!report(r, "integrate")) return false;
    std::cout << "seq=" << r.reply->seq << (r.reply->duplicate ? " duplicate" : " applied")
              << " touched=" << r.reply->voxels_touched << " hit=" << r.reply->voxels_hit
              << " freed=" << r.reply->voxels_freed << " version=" << r.reply->map_version
              << " attempts=" << r.attempts << '\n';
    return true;
  }
};

// Every subcommand; exactly one is parsed.
struct Commands {
  StatsCommand stats;
  PoseCommand pose;
  KeyframesCommand keyframes;
  MapCommand map;
  RenderCommand render;
  ChunkCommand chunk;
  IntegrateCommand integrate;
  TrackingCommand tracking;

  void add(CLI::App& app) {
    stats.add(app);
    pose.add(app);
    keyframes.add(app);
    map.add(app);
    render.add(app);
    chunk.add(app);
    integrate.add(app);
    tracking.add(app);
  }

  // The process exit code of the parsed subcommand.
  int run(MapClient& client) const {
    const auto code = [](bool ok) { return ok ? 0 : 1; };
    if (stats.command->parsed()) return code(stats.run(client));
    if (pose.command->parsed()) return code(pose.run(client));
    if (keyframes.command->parsed()) return code(keyframes.run(client));
    if (map.parsed()) return code(map.run(client));
    if (render.command->parsed()) return code(render.run(client));
    if (chunk.command->parsed()) return chunk.run(client);
    if (tracking.command->parsed()) return code(tracking.run(client));
    if (integrate.command->parsed()) return code(integrate.run(client));
    return 2;
  }
};

void addClientOptions(CLI::App& app, socc::rpc::ClientOptions& options, int& timeout_ms) {
  app.add_option("--lcm-url", options.lcm_url,
                 "LCM URL (udpm://239.x.y.z:port?ttl=0; ttl=1 on a LAN only with --key-file, "
                 "docs/fleet.md); add &recv_buf_size=67108864 for big chunks")
      ->capture_default_str();
  app.add_option("--client-id", options.client_id, "client / robot id")->capture_default_str();
  app.add_option("--timeout-ms", timeout_ms, "per attempt")->capture_default_str();
  app.add_option("--attempts", options.max_attempts, "attempts per call")->capture_default_str();
  app.add_option("--key-file", options.key_file,
                 "shared key (mode 0600) to sign requests with, if map_server has --key-file");
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"socc-cli: talk to map_server over LCM"};
  app.set_version_flag("--version", socc::versionLine("socc-cli"));
  app.require_subcommand(1);
  socc::rpc::ClientOptions options;
  options.lcm_url = std::string(socc::channels::kDefaultLcmUrl);
  options.client_id = "socc-cli";
  int timeout_ms = 2000;
  addClientOptions(app, options, timeout_ms);
  Commands commands;
  commands.add(app);
  CLI11_PARSE(app, argc, argv);
  options.timeout = std::chrono::milliseconds(timeout_ms);
  try {
    MapClient client(options);
    return commands.run(client);
  } catch (const std::exception& e) {
    std::cerr << "socc-cli: " << e.what() << '\n';
    return 1;
  }
}
