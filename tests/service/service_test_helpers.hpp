#pragma once
// Shared helpers of the service unit tests: small deterministic scans and a comparable
// fingerprint of a chunk answer.
#include <cmath>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "../temp_dir.hpp"
#include "service/map_service.hpp"
#include "socc/channels.hpp"
#include "socc/labels.hpp"
#include "socc/pose_conversion.hpp"
#include "socc/rpc/map_client.hpp"

namespace socc::service::test {

inline ServerConfig smallConfig(const std::filesystem::path& file_dir = ".") {
  ServerConfig config;
  config.map.voxel_size = 0.5;
  config.map.max_range = 40.0;
  config.map.max_points_per_scan = 5000;
  config.file_dir = file_dir;
  return config;
}

/// A few hundred labelled points of a walled yard, seen from (x, 0, 0).
inline integrate_request_t scan(const std::string& robot, std::int64_t seq, double x = 0.0) {
  std::mt19937 rng(static_cast<std::uint32_t>(seq * 7919 + 13));
  std::uniform_real_distribution<float> u(-8.0f, 8.0f);
  LabeledCloud cloud;
  for (int i = 0; i < 300; ++i) {
    cloud.points.emplace_back(u(rng), u(rng), -1.5f);
    cloud.labels.push_back(kRoad);
    cloud.points.emplace_back(9.0f, u(rng), 0.1f * u(rng));
    cloud.labels.push_back(kBuilding);
  }
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation().x() = x;
  integrate_request_t request = rpc::makeIntegrateRequest(seq, seq * 100000, pose, cloud);
  request.header.client_id = robot;
  request.header.reply_channel = channels::reply(channels::kIntegrate, robot);
  return request;
}

/// A ROBOT_STATUS report of robot (robot_status_request_t state) about frame seq.
inline robot_status_request_t trackingReport(const std::string& robot, std::int8_t state,
                                             std::int64_t seq, const std::string& reason = "") {
  robot_status_request_t request{};
  request.header.client_id = robot;
  request.header.reply_channel = channels::reply(channels::kRobotStatus, robot);
  request.seq = seq;
  request.utime = seq * 100000;
  request.tracking_state = state;
  request.reason = reason;
  return request;
}

inline chunk_request_t everything() {
  chunk_request_t request =
      rpc::sphereChunkRequest(Eigen::Vector3d::Zero(), 60.0,
                              chunk_request_t::FIELD_FEATURES | chunk_request_t::FIELD_STATS |
                                  chunk_request_t::FIELD_INDEX | chunk_request_t::FIELD_FREE);
  request.header.client_id = "tester";
  return request;
}

/// Encoded chunk content without the per-call header and the version counter.
inline std::vector<std::uint8_t> content(chunk_reply_t reply) {
  reply.header = reply_header_t{};
  reply.map_version = 0;
  reply.map_epoch = 0;  // random per map instance
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(reply.getEncodedSize()));
  reply.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

template <typename Message>
std::vector<std::uint8_t> encode(const Message& message) {
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(message.getEncodedSize()));
  message.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

using TempDir = socc::testing::TempDir;

}  // namespace socc::service::test
