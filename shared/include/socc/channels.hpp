#pragma once
// LCM channel naming convention (documented in README.md):
//   requests   SOCC/<SERVICE>/REQ
//   replies    SOCC/<SERVICE>/REP/<client_id>
//   status     SOCC/STATUS            (map_stats_t, 1 Hz)
//   scans      SOCC/SCAN/<robot_id>   (scan_t, from drivers or lcm-logplayer)
//   view       SOCC/MAP_DELTA         (map_delta_t: changed blocks for live views, socc-view)
#include <array>
#include <string>
#include <string_view>

namespace socc::channels {

inline constexpr std::string_view kIntegrate = "INTEGRATE";
inline constexpr std::string_view kGetChunk = "GET_CHUNK";
inline constexpr std::string_view kGetStats = "GET_STATS";
inline constexpr std::string_view kGetRobotPose = "GET_ROBOT_POSE";
inline constexpr std::string_view kMapCommand = "MAP_COMMAND";
inline constexpr std::string_view kRender = "RENDER";
inline constexpr std::string_view kRobotStatus = "ROBOT_STATUS";
inline constexpr std::string_view kLocalize = "LOCALIZE";
inline constexpr std::string_view kGetKeyframes = "GET_KEYFRAMES";

/// Every service: the server subscribes to each request channel, a client to each reply channel.
inline constexpr std::array<std::string_view, 9> kServices = {
    kIntegrate, kGetChunk,    kGetStats, kGetRobotPose, kMapCommand,
    kRender,    kRobotStatus, kLocalize, kGetKeyframes};

inline constexpr std::string_view kStatus = "SOCC/STATUS";
inline constexpr std::string_view kMapDelta = "SOCC/MAP_DELTA";

/// The default LCM URL: UDP multicast that never leaves this machine (ttl=0).
inline constexpr std::string_view kDefaultLcmUrl = "udpm://239.255.76.67:7667?ttl=0";

inline std::string request(std::string_view service) {
  return "SOCC/" + std::string(service) + "/REQ";
}
inline std::string reply(std::string_view service, std::string_view client_id) {
  return "SOCC/" + std::string(service) + "/REP/" + std::string(client_id);
}
inline std::string scan(std::string_view robot_id) {
  return "SOCC/SCAN/" + std::string(robot_id);
}

}  // namespace socc::channels
