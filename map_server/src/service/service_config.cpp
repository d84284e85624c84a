#include "service_config.hpp"

#include <yaml-cpp/yaml.h>

#include <set>
#include <stdexcept>
#include <string>

namespace socc::service {
namespace {

void rejectUnknownKeys(const YAML::Node& node, const std::set<std::string>& known,
                       const std::string& where) {
  for (const auto& entry : node) {
    const auto key = entry.first.as<std::string>();
    if (known.count(key) == 0) throw std::runtime_error("unknown key '" + where + key + "'");
  }
}

// section.key, if present, into value; it must be > 0 (>= 0 with allow_zero).
template <typename T>
void readNumber(const YAML::Node& section, const std::string& where, const char* key, T& value,
                bool allow_zero = false) {
  if (!section[key]) return;
  try {
    value = section[key].as<T>();
  } catch (const YAML::Exception&) {
    throw std::runtime_error(where + key + ": not a number");
  }
  if (!(value > 0 || (allow_zero && value == 0)))
    throw std::runtime_error(where + key + (allow_zero ? ": must be >= 0" : ": must be > 0"));
}

bool readBool(const YAML::Node& node, const std::string& key) {
  try {
    return node.as<bool>();
  } catch (const YAML::Exception&) {
    throw std::runtime_error(key + ": expected true or false");
  }
}

YAML::Node yamlSection(const YAML::Node& root, const char* name) {
  const YAML::Node node = root[name];
  if (node && !node.IsMap()) throw std::runtime_error(std::string(name) + ": expected a mapping");
  return node;
}

void readLimits(const YAML::Node& limits, ServiceLimits& out) {
  rejectUnknownKeys(
      limits,
      {"max_chunk_voxels", "max_region_extent", "max_reply_bytes", "max_render_pixels",
       "max_robots", "max_localize_points", "robot_integrate_rate", "robot_chunk_rate"},
      "limits.");
  readNumber(limits, "limits.", "max_chunk_voxels", out.max_chunk_voxels);
  readNumber(limits, "limits.", "max_region_extent", out.max_region_extent);
  readNumber(limits, "limits.", "max_reply_bytes", out.max_reply_bytes);
  readNumber(limits, "limits.", "max_render_pixels", out.max_render_pixels);
  readNumber(limits, "limits.", "max_robots", out.max_robots);
  readNumber(limits, "limits.", "max_localize_points", out.max_localize_points);
  readNumber(limits, "limits.", "robot_integrate_rate", out.robot_integrate_rate);
  readNumber(limits, "limits.", "robot_chunk_rate", out.robot_chunk_rate);
}

void readPlausibility(const YAML::Node& node, PlausibilityLimits& out) {
  const std::string where = "plausibility.";
  rejectUnknownKeys(
      node, {"enabled", "max_linear_speed", "max_angular_speed", "linear_slack", "angular_slack"},
      where);
  if (node["enabled"]) out.enabled = readBool(node["enabled"], where + "enabled");
  readNumber(node, where, "max_linear_speed", out.max_linear_speed);
  readNumber(node, where, "max_angular_speed", out.max_angular_speed);
  readNumber(node, where, "linear_slack", out.linear_slack, true);
  readNumber(node, where, "angular_slack", out.angular_slack, true);
}

}  // namespace

ServerConfig loadServerConfig(const std::filesystem::path& file) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(file.string());
  } catch (const YAML::Exception& e) {
    throw std::runtime_error("cannot read server config " + file.string() + ": " + e.what());
  }
  ServerConfig config;
  if (root.IsNull()) return config;
  if (!root.IsMap()) throw std::runtime_error(file.string() + ": expected a YAML mapping");
  rejectUnknownKeys(
      root, {"map_config", "file_dir", "key_file", "auth_queries", "limits", "plausibility"}, "");

  if (root["map_config"]) {
    std::filesystem::path map_file = root["map_config"].as<std::string>();
    if (map_file.is_relative()) map_file = file.parent_path() / map_file;
    config.map = map::loadMapConfig(map_file);
  }
  if (root["file_dir"]) config.file_dir = root["file_dir"].as<std::string>();
  if (root["key_file"]) {
    config.key_file = root["key_file"].as<std::string>();
    if (config.key_file.is_relative()) config.key_file = file.parent_path() / config.key_file;
  }
  if (root["auth_queries"]) config.auth_queries = readBool(root["auth_queries"], "auth_queries");
  if (const YAML::Node limits = yamlSection(root, "limits")) readLimits(limits, config.limits);
  if (const YAML::Node gate = yamlSection(root, "plausibility"))
    readPlausibility(gate, config.plausibility);
  return config;
}

}  // namespace socc::service
