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

template <typename T>
void readPositive(const YAML::Node& node, const char* key, T& value) {
  if (!node[key]) return;
  try {
    value = node[key].as<T>();
  } catch (const YAML::Exception&) {
    throw std::runtime_error(std::string("limits.") + key + ": not a number");
  }
  if (!(value > 0)) throw std::runtime_error(std::string("limits.") + key + ": must be > 0");
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
  rejectUnknownKeys(root, {"map_config", "file_dir", "key_file", "auth_queries", "limits"}, "");

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
  if (root["auth_queries"]) {
    try {
      config.auth_queries = root["auth_queries"].as<bool>();
    } catch (const YAML::Exception&) {
      throw std::runtime_error("auth_queries: expected true or false");
    }
  }
  if (const YAML::Node limits = root["limits"]) {
    if (!limits.IsMap()) throw std::runtime_error("limits: expected a mapping");
    rejectUnknownKeys(limits,
                      {"max_chunk_voxels", "max_region_extent", "max_reply_bytes",
                       "max_render_pixels", "max_robots"},
                      "limits.");
    readPositive(limits, "max_chunk_voxels", config.limits.max_chunk_voxels);
    readPositive(limits, "max_region_extent", config.limits.max_region_extent);
    readPositive(limits, "max_reply_bytes", config.limits.max_reply_bytes);
    readPositive(limits, "max_render_pixels", config.limits.max_render_pixels);
    readPositive(limits, "max_robots", config.limits.max_robots);
  }
  return config;
}

}  // namespace socc::service
