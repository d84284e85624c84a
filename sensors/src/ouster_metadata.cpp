#include "ouster_metadata.hpp"

#include <cctype>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>

namespace socc::sensors {
namespace {

using nlohmann::json;

// Where a key lives: firmware 3.x nests it in a section, 2.x has it at the top level or in
// data_format.
const json* findMetadataKey(const json& root, const char* section, const char* key) {
  if (root.contains(section) && root[section].is_object() && root[section].contains(key))
    return &root[section][key];
  if (root.contains(key)) return &root[key];
  if (root.contains("data_format") && root["data_format"].is_object() &&
      root["data_format"].contains(key))
    return &root["data_format"][key];
  return nullptr;
}

class MetadataReader {
 public:
  MetadataReader(const json& root, std::string file) : root_(root), file_(std::move(file)) {}

  const json& need(const char* section, const char* key) const {
    const json* v = findMetadataKey(root_, section, key);
    if (!v || v->is_null()) throw error(std::string("has no ") + key);
    return *v;
  }
  const json* optional(const char* section, const char* key) const {
    const json* v = findMetadataKey(root_, section, key);
    return v && !v->is_null() ? v : nullptr;
  }
  std::vector<double> numbers(const json& v, const char* key, std::size_t count) const {
    if (!v.is_array() || (count && v.size() != count))
      throw error(std::string(key) + " must be an array of " + std::to_string(count) + " numbers");
    std::vector<double> out;
    for (const json& x : v) {
      if (!x.is_number() || !std::isfinite(x.get<double>()))
        throw error(std::string(key) + " holds a value that is not a finite number");
      out.push_back(x.get<double>());
    }
    return out;
  }
  int integer(const json& v, const char* key) const {
    if (!v.is_number_integer()) throw error(std::string(key) + " must be an integer");
    return v.get<int>();
  }
  std::runtime_error error(const std::string& what) const {
    return std::runtime_error(file_ + ": Ouster metadata " + what);
  }

 private:
  const json& root_;
  std::string file_;
};

std::array<double, 16> metadataMatrix(const MetadataReader& r, const json& v, const char* key) {
  const auto n = r.numbers(v, key, 16);
  std::array<double, 16> m{};
  std::copy(n.begin(), n.end(), m.begin());
  if (m[12] != 0 || m[13] != 0 || m[14] != 0 || m[15] != 1)
    throw r.error(std::string(key) + " is not a homogeneous transform");
  return m;
}

std::array<double, 16> identityMatrix() {
  std::array<double, 16> m{};
  m[0] = m[5] = m[10] = m[15] = 1.0;
  return m;
}

OusterProfile ousterProfileOf(const std::string& name, const MetadataReader& r) {
  if (name == "LEGACY") return OusterProfile::kLegacy;
  if (name == "RNG19_RFL8_SIG16_NIR16") return OusterProfile::kSingle;
  if (name == "RNG15_RFL8_NIR8") return OusterProfile::kLowData;
  if (name == "RNG19_RFL8_SIG16_NIR16_DUAL") return OusterProfile::kDual;
  throw r.error("lidar profile " + name +
                " is not supported (LEGACY, RNG19_RFL8_SIG16_NIR16, RNG15_RFL8_NIR8, "
                "RNG19_RFL8_SIG16_NIR16_DUAL are)");
}

}  // namespace

int OusterMetadata::windowColumns() const {
  return window_first <= window_last ? window_last - window_first + 1
                                     : columns_per_frame - window_first + window_last + 1;
}

bool OusterMetadata::inWindow(int column) const {
  return window_first <= window_last ? column >= window_first && column <= window_last
                                     : column >= window_first || column <= window_last;
}

std::string ousterModelName(const std::string& prod_line) {
  // "OS-1-128", "OS1-64", "OS-0-128-U13" ...: "os", an optional '-', the family digit, '-',
  // the beam count, then the end or a further '-' or ' ' field.
  std::string lower;
  for (const char c : prod_line)
    lower += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (lower.rfind("os", 0) != 0) return {};
  std::size_t at = lower.size() > 2 && lower[2] == '-' ? 3 : 2;
  if (at + 2 > lower.size() || lower[at] < '0' || lower[at] > '2' || lower[at + 1] != '-')
    return {};
  const char family = lower[at];
  at += 2;
  const std::size_t end = lower.find_first_of("- ", at);
  const std::string beams =
      lower.substr(at, end == std::string::npos ? std::string::npos : end - at);
  if (beams != "16" && beams != "32" && beams != "64" && beams != "128") return {};
  return std::string("os") + family + "-" + beams;
}

OusterMetadata readOusterMetadata(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file.string() + ": cannot open the Ouster metadata");
  json root;
  try {
    root = json::parse(in);
  } catch (const json::exception& e) {
    throw std::runtime_error(file.string() + ": not a JSON file (" + e.what() + ")");
  }
  if (!root.is_object()) throw std::runtime_error(file.string() + ": not an Ouster metadata JSON");
  const MetadataReader r(root, file.string());
  OusterMetadata md;
  try {
    md.prod_line = r.need("sensor_info", "prod_line").get<std::string>();
    md.model = ousterModelName(md.prod_line);
    if (md.model.empty())
      throw r.error("product line \"" + md.prod_line + "\" is not an OS0, OS1 or OS2");
    if (const json* sn = r.optional("sensor_info", "prod_sn"); sn && sn->is_string()) {
      const std::string s = sn->get<std::string>();
      if (!s.empty() && s.find_first_not_of("0123456789") == std::string::npos && s.size() < 19)
        md.serial = std::stoull(s);
    }
    if (const json* id = r.optional("sensor_info", "initialization_id"))
      md.init_id = static_cast<std::uint32_t>(r.integer(*id, "initialization_id"));
    md.beam_altitude_deg =
        r.numbers(r.need("beam_intrinsics", "beam_altitude_angles"), "beam_altitude_angles", 0);
    const std::size_t beams = md.beam_altitude_deg.size();
    md.beam_azimuth_deg =
        r.numbers(r.need("beam_intrinsics", "beam_azimuth_angles"), "beam_azimuth_angles", beams);
    for (std::size_t i = 0; i < beams; ++i)
      if (std::abs(md.beam_altitude_deg[i]) > 90 || std::abs(md.beam_azimuth_deg[i]) > 45)
        throw r.error("beam " + std::to_string(i) + " has implausible angles");
    md.beam_to_lidar = identityMatrix();
    if (const json* bl = r.optional("beam_intrinsics", "beam_to_lidar_transform")) {
      md.beam_to_lidar = metadataMatrix(r, *bl, "beam_to_lidar_transform");
    } else {
      md.beam_to_lidar[3] =
          r.need("beam_intrinsics", "lidar_origin_to_beam_origin_mm").get<double>();
    }
    md.lidar_to_sensor = metadataMatrix(r, r.need("lidar_intrinsics", "lidar_to_sensor_transform"),
                                        "lidar_to_sensor_transform");

    // lidar_mode "1024x10": columns per frame x frames per second.
    const std::string mode = r.need("config_params", "lidar_mode").get<std::string>();
    const std::size_t x = mode.find('x');
    const std::string columns_text = mode.substr(0, x),
                      rate_text = x == std::string::npos ? "" : mode.substr(x + 1);
    if ((columns_text != "512" && columns_text != "1024" && columns_text != "2048" &&
         columns_text != "4096") ||
        (rate_text != "5" && rate_text != "10" && rate_text != "20"))
      throw r.error("lidar_mode \"" + mode + "\"");
    md.frequency_hz = std::stod(rate_text);
    const int mode_columns = std::stoi(columns_text);

    md.pixels_per_column = static_cast<int>(beams);
    md.columns_per_frame = mode_columns;
    md.window_last = mode_columns - 1;
    md.profile_name = "LEGACY";
    if (const json* v = r.optional("lidar_data_format", "pixels_per_column"))
      md.pixels_per_column = r.integer(*v, "pixels_per_column");
    if (const json* v = r.optional("lidar_data_format", "columns_per_frame"))
      md.columns_per_frame = r.integer(*v, "columns_per_frame");
    if (const json* v = r.optional("lidar_data_format", "columns_per_packet"))
      md.columns_per_packet = r.integer(*v, "columns_per_packet");
    if (const json* v = r.optional("lidar_data_format", "column_window")) {
      const auto w = r.numbers(*v, "column_window", 2);
      if (w[0] < 0 || w[1] < 0 || w[0] >= md.columns_per_frame || w[1] >= md.columns_per_frame)
        throw r.error("column_window outside the frame");
      md.window_first = static_cast<int>(w[0]);
      md.window_last = static_cast<int>(w[1]);
    }
    if (const json* v = r.optional("lidar_data_format", "udp_profile_lidar"))
      md.profile_name = v->get<std::string>();
    else if (const json* c = r.optional("config_params", "udp_profile_lidar"))
      md.profile_name = c->get<std::string>();
    md.profile = ousterProfileOf(md.profile_name, r);
  } catch (const nlohmann::json::exception& e) {
    throw r.error(std::string("has a field of the wrong type (") + e.what() + ")");
  }

  const std::string beams_in_name = md.model.substr(md.model.find('-') + 1);
  if (md.pixels_per_column != static_cast<int>(md.beam_altitude_deg.size()) ||
      std::to_string(md.pixels_per_column) != beams_in_name)
    throw r.error("pixels_per_column " + std::to_string(md.pixels_per_column) + " and " +
                  std::to_string(md.beam_altitude_deg.size()) + " beam angles disagree with " +
                  md.prod_line);
  if (md.columns_per_frame != 512 && md.columns_per_frame != 1024 && md.columns_per_frame != 2048 &&
      md.columns_per_frame != 4096)
    throw r.error("columns_per_frame " + std::to_string(md.columns_per_frame));
  if (md.columns_per_packet < 1 || md.columns_per_packet > 64 ||
      md.columns_per_frame % md.columns_per_packet != 0)
    throw r.error("columns_per_packet " + std::to_string(md.columns_per_packet));
  if (md.window_first < 0 || md.window_last < 0 || md.window_first >= md.columns_per_frame ||
      md.window_last >= md.columns_per_frame)
    throw r.error("column_window [" + std::to_string(md.window_first) + ", " +
                  std::to_string(md.window_last) + "] outside the frame");
  return md;
}

}  // namespace socc::sensors
