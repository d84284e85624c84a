#pragma once
// The Foxglove WebSocket protocol (subprotocol foxglove.websocket.v1) as socc-view speaks it on
// /foxglove: serverInfo and advertise (JSON text), client subscribe/unsubscribe (JSON text),
// messageData frames (binary: opcode 0x01, u32 subscription id, u64 timestamp [ns], payload).
// Every channel is JSON-encoded with a Foxglove schema name (foxglove.PointCloud,
// foxglove.SceneUpdate, foxglove.FrameTransform) and a JSON Schema of its fields.
#include <cstdint>
#include <string>
#include <vector>

#include "view_model.hpp"

namespace socc::view::foxglove {

inline constexpr const char* kSubprotocol = "foxglove.websocket.v1";

enum Channel : std::uint32_t {
  kVoxels = 1,      // /map/voxels: the map's occupied voxels (foxglove.PointCloud)
  kScans = 2,       // /robots/scans: every robot's latest scan (foxglove.PointCloud)
  kRobots = 3,      // /robots/markers: pose, trajectory, tracking state (foxglove.SceneUpdate)
  kTransforms = 4,  // /tf: map -> <robot id> (foxglove.FrameTransform, one per robot)
  kStats = 5,       // /map/stats: the map server's statistics (JSON)
};
inline constexpr std::uint32_t kNumChannels = 5;

std::string serverInfo(const std::string& session_id);
std::string advertise();

/// A messageData frame carrying payload for a subscription.
std::vector<std::uint8_t> messageData(std::uint32_t subscription, std::uint64_t time_ns,
                                      const std::string& payload);

/// The payloads (JSON). voxels: at most max_points voxel centres (every k-th beyond that),
/// coloured by class.
std::string voxels(const ViewModel& model, std::uint64_t time_ns, std::size_t max_points);
std::string scans(const ViewModel& model, std::uint64_t time_ns);
std::string robots(const ViewModel& model, std::uint64_t time_ns);
std::vector<std::string> transforms(const ViewModel& model, std::uint64_t time_ns);

}  // namespace socc::view::foxglove
