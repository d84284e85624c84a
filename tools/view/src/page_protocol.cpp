#include "page_protocol.hpp"

#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>

#include "socc/labels.hpp"
#include "socc/rpc/status_names.hpp"

namespace socc::view::page {
namespace {

using nlohmann::json;

template <typename T>
void put(std::vector<std::uint8_t>& out, T value) {  // little-endian hosts only (x86, arm)
  const auto at = out.size();
  out.resize(at + sizeof(T));
  std::memcpy(out.data() + at, &value, sizeof(T));
}

json poseJson(const RobotView& r) {
  return {{"t", r.translation}, {"q", r.quaternion}};
}

}  // namespace

std::string hello(const ViewModel& model) {
  json classes = json::array();
  for (int c = 0; c < kNumClasses; ++c) {
    const Rgb rgb = classColor(static_cast<std::uint8_t>(c));
    classes.push_back({{"id", c},
                       {"name", std::string(className(static_cast<std::uint8_t>(c)))},
                       {"color", {rgb.r, rgb.g, rgb.b}}});
  }
  json states = json::array();
  for (std::int8_t s = 0; s <= 3; ++s) states.push_back(rpc::trackingStateName(s));
  return json{{"type", "hello"},
              {"voxel_size", model.voxelSize()},
              {"block_dim", model.blockDim()},
              {"classes", classes},
              {"tracking_states", states}}
      .dump();
}

std::string reset() {
  return json{{"type", "reset"}}.dump();
}

std::string stats(const ViewModel& model) {
  if (!model.stats()) return {};
  const map_stats_t& s = *model.stats();
  return json{{"type", "stats"},
              {"server_version", s.server_version},
              {"voxel_size", s.voxel_size},
              {"num_voxels", s.num_voxels},
              {"num_occupied", s.num_occupied},
              {"num_free", s.num_free},
              {"num_blocks", s.num_blocks},
              {"memory_bytes", s.memory_bytes},
              {"map_version", s.map_version},
              {"integrations", s.integrations},
              {"integrations_per_s", s.integrations_per_s},
              {"requests", s.requests},
              {"rejected_requests", s.rejected_requests},
              {"auth_failures", s.auth_failures},
              {"num_robots", s.num_robots},
              {"view_voxels", model.voxelCount()},
              {"view_blocks", model.blocks().size()}}
      .dump();
}

std::string robots(const ViewModel& model, std::map<std::string, std::size_t>& sent_points) {
  json list = json::array();
  for (const auto& [id, r] : model.robots()) {
    std::size_t& sent = sent_points[id];
    if (sent > r.trajectory.size()) sent = 0;  // cannot shrink: start again
    json points = json::array();
    for (std::size_t i = sent; i < r.trajectory.size(); ++i)
      points.push_back({r.trajectory[i][0], r.trajectory[i][1], r.trajectory[i][2]});
    list.push_back({{"id", id},
                    {"pose", poseJson(r)},
                    {"seq", r.last_seq},
                    {"integrations", r.integrations},
                    {"refused", r.refused},
                    {"tracking_state", r.tracking_state},
                    {"tracking_name", rpc::trackingStateName(r.tracking_state)},
                    {"reason", r.tracking_reason},
                    {"trajectory_from", sent},
                    {"trajectory", points}});
    sent = r.trajectory.size();
  }
  return json{{"type", "robots"}, {"robots", list}}.dump();
}

std::size_t blocks(const ViewModel& model, const std::vector<BlockKey>& keys, std::size_t first,
                   std::size_t max_bytes, std::vector<std::uint8_t>& out) {
  out.clear();
  put<std::uint8_t>(out, kBlocks);
  for (int i = 0; i < 3; ++i) put<std::uint8_t>(out, 0);
  put<std::uint32_t>(out, 0);  // block count, written at the end
  std::uint32_t n = 0;
  std::size_t i = first;
  for (; i < keys.size() && (n == 0 || out.size() < max_bytes); ++i, ++n) {
    const auto it = model.blocks().find(keys[i]);
    const std::size_t count = it == model.blocks().end() ? 0 : it->second.local.size();
    for (const std::int32_t k : keys[i]) put<std::int32_t>(out, k);
    put<std::uint16_t>(out, static_cast<std::uint16_t>(count));
    for (std::size_t v = 0; v < count; ++v) {
      put<std::uint16_t>(out, static_cast<std::uint16_t>(it->second.local[v]));
      put<std::uint8_t>(out, it->second.occupancy[v]);
      put<std::uint8_t>(out, it->second.label[v]);
    }
  }
  std::memcpy(out.data() + 4, &n, sizeof(n));
  return i - first;
}

std::vector<std::uint8_t> scan(const RobotView& robot) {
  std::vector<std::uint8_t> out;
  put<std::uint8_t>(out, kScan);
  put<std::uint8_t>(out, static_cast<std::uint8_t>(robot.id.size()));  // ids: <= 64 chars
  out.insert(out.end(), robot.id.begin(), robot.id.end());
  const std::size_t count_at = out.size();
  put<std::uint32_t>(out, 0);
  float origin[3];
  for (int a = 0; a < 3; ++a) {
    origin[a] = static_cast<float>(robot.translation[a]);
    put<float>(out, origin[a]);
  }
  std::uint32_t n = 0;
  for (std::size_t i = 0; i + 2 < robot.scan.size(); i += 3) {
    std::int16_t q[3];
    bool fits = true;
    for (int a = 0; a < 3; ++a) {
      const float steps = std::round((robot.scan[i + a] - origin[a]) / kScanStep);
      fits = fits && std::abs(steps) <= 32767.0f;
      q[a] = fits ? static_cast<std::int16_t>(steps) : 0;
    }
    if (!fits) continue;  // beyond +-655 m of the robot
    for (const std::int16_t v : q) put<std::int16_t>(out, v);
    ++n;
  }
  std::memcpy(out.data() + count_at, &n, sizeof(n));
  return out;
}

}  // namespace socc::view::page
