// socc-monitor: example client of the socc map service, built against the installed package
// (examples/socc-monitor/CMakeLists.txt). It asks GET_STATS, picks a robot, fetches the chunk
// around the robot's last pose and prints the occupancy along a line ahead of it.
// Plain argument parsing: the package exports no command-line library, only the client.
#include <Eigen/Geometry>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <map>
#include <set>
#include <string>
#include <tuple>

#include "socc/channels.hpp"
#include "socc/labels.hpp"
#include "socc/pose_conversion.hpp"
#include "socc/rpc/map_client.hpp"
#include "socc/version.hpp"

namespace {

using Key = std::tuple<int, int, int>;

struct Options {
  socc::rpc::ClientOptions client;
  std::string robot;     // empty: the first robot in the stats
  double length = 20.0;  // of the line ahead of the robot [m]
};

const char* const kUsage =
    "usage: socc-monitor [--lcm-url URL] [--robot ID] [--length M] [--timeout-ms MS]\n"
    "  Prints the map server's stats (version, voxels, robots), then the occupancy along a\n"
    "  line of M metres (default 20) ahead of a robot's last pose: '#' occupied (with the\n"
    "  class of the first hit), '.' free, ' ' unknown. URL: udpm://239.x.y.z:port?ttl=0.\n";

// Returns false (and sets exit_code) when the program should stop: --help, --version, errors.
bool parse(int argc, char** argv, Options& o, int& exit_code) {
  o.client.lcm_url = std::string(socc::channels::kDefaultLcmUrl);
  o.client.client_id = "monitor";
  o.client.max_attempts = 2;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (arg == "--help" || arg == "-h") {
      std::cout << kUsage;
      exit_code = 0;
      return false;
    } else if (arg == "--version") {
      std::cout << socc::versionLine("socc-monitor") << '\n';
      exit_code = 0;
      return false;
    } else if (arg == "--lcm-url" && has_value) {
      o.client.lcm_url = argv[++i];
    } else if (arg == "--robot" && has_value) {
      o.robot = argv[++i];
    } else if (arg == "--length" && has_value) {
      o.length = std::atof(argv[++i]);
    } else if (arg == "--timeout-ms" && has_value) {
      o.client.timeout = std::chrono::milliseconds(std::atoi(argv[++i]));
    } else {
      std::cerr << "socc-monitor: bad argument '" << arg << "'\n" << kUsage;
      exit_code = 2;
      return false;
    }
  }
  return true;
}

// The line from the robot's position along its x axis, one character per voxel.
void printLine(const socc::chunk_reply_t& chunk, const Eigen::Isometry3d& pose, double length) {
  std::map<Key, int> occupied;  // voxel index -> position in the reply arrays
  std::set<Key> free;
  for (int i = 0; i < chunk.n_index; ++i)
    occupied[{chunk.index[0][i], chunk.index[1][i], chunk.index[2][i]}] = i;
  for (int i = 0; i < chunk.n_free; ++i)
    free.insert({chunk.free_index[0][i], chunk.free_index[1][i], chunk.free_index[2][i]});
  const double step = chunk.voxel_size;
  std::string line;
  std::string first_hit = "none";
  for (double s = 0.0; s <= length; s += step) {
    const Eigen::Vector3d p = pose * Eigen::Vector3d(s, 0.0, 0.0);
    const Key key{static_cast<int>(std::floor(p.x() / step)),
                  static_cast<int>(std::floor(p.y() / step)),
                  static_cast<int>(std::floor(p.z() / step))};
    if (const auto it = occupied.find(key); it != occupied.end()) {
      line += '#';
      if (first_hit == "none" && it->second < chunk.n_features)
        first_hit = std::string(socc::className(chunk.label[it->second])) + " at " +
                    std::to_string(s) + " m";
    } else {
      line += free.count(key) ? '.' : ' ';
    }
  }
  std::cout << "line ahead (" << length << " m, " << step << " m/char): [" << line << "]\n"
            << "first occupied: " << first_hit << '\n';
}

int monitor(const Options& o) {
  socc::rpc::MapClient client(o.client);
  const auto stats = client.getStats();
  if (!stats.ok()) {
    std::cerr << "socc-monitor: GET_STATS: " << stats.error.message << '\n';
    return 1;
  }
  const socc::map_stats_t& s = stats.reply->stats;
  std::cout << "server " << s.server_version << " (monitor " << socc::kVersion
            << "): " << s.num_voxels << " voxels, " << s.num_occupied << " occupied, "
            << s.num_robots << " robots\n";
  const socc::robot_state_t* robot = nullptr;
  for (const auto& r : s.robots)
    if (!robot && (o.robot.empty() || r.robot_id == o.robot)) robot = &r;
  if (!robot) {
    std::cout << "no robot " << (o.robot.empty() ? "in the map" : "'" + o.robot + "'") << '\n';
    return o.robot.empty() ? 0 : 1;
  }
  const Eigen::Isometry3d pose = socc::fromLcm(robot->last_pose);
  std::cout << "robot " << robot->robot_id << " at " << pose.translation().transpose() << " (seq "
            << robot->last_seq << ")\n";
  const auto chunk = client.getChunk(socc::rpc::sphereChunkRequest(
      pose.translation(), o.length + 1.0,
      socc::chunk_request_t::FIELD_FEATURES | socc::chunk_request_t::FIELD_INDEX |
          socc::chunk_request_t::FIELD_FREE));
  if (!chunk.ok()) {
    std::cerr << "socc-monitor: GET_CHUNK: " << chunk.error.message << '\n';
    return 1;
  }
  printLine(*chunk.reply, pose, o.length);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  int exit_code = 0;
  if (!parse(argc, argv, options, exit_code)) return exit_code;
  try {
    return monitor(options);
  } catch (const std::exception& e) {
    std::cerr << "socc-monitor: " << e.what() << '\n';
    return 1;
  }
}
