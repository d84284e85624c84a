#include "foxglove_protocol.hpp"

#include <openssl/evp.h>

#include <cstring>
#include <nlohmann/json.hpp>

#include "socc/labels.hpp"
#include "socc/rpc/status_names.hpp"

namespace socc::view::foxglove {
namespace {

using nlohmann::json;

constexpr int kUint8 = 1;  // foxglove.PackedElementField numeric types
constexpr int kFloat32 = 7;
constexpr std::size_t kPointStride = 16;  // x y z float32, red green blue alpha uint8

json stamp(std::uint64_t ns) {
  return {{"sec", ns / 1000000000u}, {"nsec", ns % 1000000000u}};
}

json vec3(double x, double y, double z) {
  return {{"x", x}, {"y", y}, {"z", z}};
}
json identityPose() {
  return {{"position", vec3(0, 0, 0)}, {"orientation", {{"x", 0}, {"y", 0}, {"z", 0}, {"w", 1}}}};
}
json poseOf(const RobotView& r) {
  return {{"position", vec3(r.translation[0], r.translation[1], r.translation[2])},
          {"orientation",
           {{"x", r.quaternion[1]},
            {"y", r.quaternion[2]},
            {"z", r.quaternion[3]},
            {"w", r.quaternion[0]}}}};
}
json color(double r, double g, double b, double a = 1.0) {
  return {{"r", r}, {"g", g}, {"b", b}, {"a", a}};
}

// Healthy green, degraded amber, lost / relocalizing red (the page uses the same colours).
json stateColor(std::int8_t state) {
  if (state == 0) return color(0.2, 0.8, 0.3);
  if (state == 1) return color(1.0, 0.7, 0.1);
  return color(0.9, 0.15, 0.15);
}

std::string base64(const std::vector<std::uint8_t>& bytes) {
  std::string out(4 * ((bytes.size() + 2) / 3) + 1, '\0');
  const int n = EVP_EncodeBlock(reinterpret_cast<unsigned char*>(out.data()), bytes.data(),
                                static_cast<int>(bytes.size()));
  out.resize(static_cast<std::size_t>(n));
  return out;
}

void putPoint(std::vector<std::uint8_t>& data, float x, float y, float z, Rgb c) {
  const float xyz[3] = {x, y, z};
  const std::uint8_t rgba[4] = {c.r, c.g, c.b, 255};
  const auto at = data.size();
  data.resize(at + kPointStride);
  std::memcpy(data.data() + at, xyz, sizeof(xyz));
  std::memcpy(data.data() + at + 12, rgba, sizeof(rgba));
}

json pointCloud(std::uint64_t ns, const std::vector<std::uint8_t>& data) {
  json fields = json::array();
  const char* names[] = {"x", "y", "z"};
  for (int i = 0; i < 3; ++i)
    fields.push_back({{"name", names[i]}, {"offset", 4 * i}, {"type", kFloat32}});
  const char* colours[] = {"red", "green", "blue", "alpha"};
  for (int i = 0; i < 4; ++i)
    fields.push_back({{"name", colours[i]}, {"offset", 12 + i}, {"type", kUint8}});
  return {{"timestamp", stamp(ns)},       {"frame_id", "map"}, {"pose", identityPose()},
          {"point_stride", kPointStride}, {"fields", fields},  {"data", base64(data)}};
}

// JSON Schemas of the messages as sent (Foxglove picks the panel by schema name; the schema
// describes the JSON fields).
json objectSchema(const std::string& title, const json& properties) {
  return {{"title", title}, {"type", "object"}, {"properties", properties}};
}
const json kTime = {
    {"type", "object"},
    {"properties", {{"sec", {{"type", "integer"}}}, {"nsec", {{"type", "integer"}}}}}};
const json kObject = {{"type", "object"}};
const json kArray = {{"type", "array"}};
const json kString = {{"type", "string"}};

std::string pointCloudSchema() {
  return objectSchema("foxglove.PointCloud",
                      {{"timestamp", kTime},
                       {"frame_id", kString},
                       {"pose", kObject},
                       {"point_stride", {{"type", "integer"}}},
                       {"fields", kArray},
                       {"data", {{"type", "string"}, {"contentEncoding", "base64"}}}})
      .dump();
}
std::string sceneUpdateSchema() {
  return objectSchema("foxglove.SceneUpdate", {{"deletions", kArray}, {"entities", kArray}}).dump();
}
std::string frameTransformSchema() {
  return objectSchema("foxglove.FrameTransform", {{"timestamp", kTime},
                                                  {"parent_frame_id", kString},
                                                  {"child_frame_id", kString},
                                                  {"translation", kObject},
                                                  {"rotation", kObject}})
      .dump();
}

json channel(Channel id, const char* topic, const char* schema_name, const std::string& schema) {
  return {{"id", id},           {"topic", topic},
          {"encoding", "json"}, {"schemaName", schema_name},
          {"schema", schema},   {"schemaEncoding", "jsonschema"}};
}

Rgb labelColor(std::uint8_t label) {
  return label == kUnlabeled ? Rgb{128, 128, 128} : classColor(label);
}

}  // namespace

std::string serverInfo(const std::string& session_id) {
  return json{{"op", "serverInfo"},
              {"name", "socc-view"},
              {"capabilities", json::array()},
              {"supportedEncodings", json::array()},
              {"metadata", json::object()},
              {"sessionId", session_id}}
      .dump();
}

std::string advertise() {
  json channels = json::array();
  channels.push_back(channel(kVoxels, "/map/voxels", "foxglove.PointCloud", pointCloudSchema()));
  channels.push_back(channel(kScans, "/robots/scans", "foxglove.PointCloud", pointCloudSchema()));
  channels.push_back(
      channel(kRobots, "/robots/markers", "foxglove.SceneUpdate", sceneUpdateSchema()));
  channels.push_back(
      channel(kTransforms, "/tf", "foxglove.FrameTransform", frameTransformSchema()));
  channels.push_back(channel(kStats, "/map/stats", "socc.MapStats",
                             objectSchema("socc.MapStats", json::object()).dump()));
  return json{{"op", "advertise"}, {"channels", channels}}.dump();
}

std::vector<std::uint8_t> messageData(std::uint32_t subscription, std::uint64_t time_ns,
                                      const std::string& payload) {
  std::vector<std::uint8_t> frame(1 + 4 + 8 + payload.size());
  frame[0] = 0x01;  // MESSAGE_DATA; little-endian hosts
  std::memcpy(frame.data() + 1, &subscription, 4);
  std::memcpy(frame.data() + 5, &time_ns, 8);
  std::memcpy(frame.data() + 13, payload.data(), payload.size());
  return frame;
}

std::string voxels(const ViewModel& model, std::uint64_t time_ns, std::size_t max_points) {
  const auto total = static_cast<std::size_t>(model.voxelCount());
  const std::size_t stride =
      max_points == 0 ? 1 : std::max<std::size_t>(1, (total + max_points - 1) / max_points);
  const double s = model.voxelSize();
  const int dim = model.blockDim();
  std::vector<std::uint8_t> data;
  data.reserve(kPointStride * (total / stride + 1));
  std::size_t i = 0;
  for (const auto& [key, block] : model.blocks())
    for (std::size_t v = 0; v < block.local.size(); ++v, ++i) {
      if (i % stride != 0) continue;
      const int l = block.local[v];
      const int x = key[0] * dim + l / (dim * dim), y = key[1] * dim + (l / dim) % dim,
                z = key[2] * dim + l % dim;
      putPoint(data, static_cast<float>((x + 0.5) * s), static_cast<float>((y + 0.5) * s),
               static_cast<float>((z + 0.5) * s), labelColor(block.label[v]));
    }
  return pointCloud(time_ns, data).dump();
}

std::string scans(const ViewModel& model, std::uint64_t time_ns) {
  std::vector<std::uint8_t> data;
  for (const auto& [id, r] : model.robots()) {
    for (std::size_t i = 0; i + 2 < r.scan.size(); i += 3)
      putPoint(data, r.scan[i], r.scan[i + 1], r.scan[i + 2], Rgb{255, 255, 255});
  }
  return pointCloud(time_ns, data).dump();
}

std::string robots(const ViewModel& model, std::uint64_t time_ns) {
  json entities = json::array();
  for (const auto& [id, r] : model.robots()) {
    json points = json::array();
    for (const auto& p : r.trajectory) points.push_back(vec3(p[0], p[1], p[2]));
    const json c = stateColor(r.tracking_state);
    json arrow = {{"pose", poseOf(r)},  {"shaft_length", 2.0},  {"shaft_diameter", 0.4},
                  {"head_length", 1.0}, {"head_diameter", 1.0}, {"color", c}};
    json line = {{"type", 0},  // LINE_STRIP
                 {"pose", identityPose()},
                 {"thickness", 0.3},
                 {"scale_invariant", false},
                 {"points", points},
                 {"color", c},
                 {"colors", json::array()},
                 {"indices", json::array()}};
    json text = {
        {"pose", poseOf(r)}, {"billboard", true},
        {"font_size", 14},   {"scale_invariant", true},
        {"color", c},        {"text", id + " " + rpc::trackingStateName(r.tracking_state)}};
    entities.push_back(
        {{"timestamp", stamp(time_ns)},
         {"frame_id", "map"},
         {"id", "robot/" + id},
         {"lifetime", stamp(0)},
         {"frame_locked", false},
         {"metadata",
          json::array({{{"key", "tracking"}, {"value", rpc::trackingStateName(r.tracking_state)}},
                       {{"key", "reason"}, {"value", r.tracking_reason}}})},
         {"arrows", json::array({arrow})},
         {"cubes", json::array()},
         {"spheres", json::array()},
         {"cylinders", json::array()},
         {"lines", json::array({line})},
         {"triangles", json::array()},
         {"texts", json::array({text})},
         {"models", json::array()}});
  }
  return json{{"deletions", json::array()}, {"entities", entities}}.dump();
}

std::vector<std::string> transforms(const ViewModel& model, std::uint64_t time_ns) {
  std::vector<std::string> out;
  for (const auto& [id, r] : model.robots())
    out.push_back(json{{"timestamp", stamp(time_ns)},
                       {"parent_frame_id", "map"},
                       {"child_frame_id", id},
                       {"translation", vec3(r.translation[0], r.translation[1], r.translation[2])},
                       {"rotation", poseOf(r)["orientation"]}}
                      .dump());
  return out;
}

}  // namespace socc::view::foxglove
