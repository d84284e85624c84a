// VeloView XML (boost-serialization archive "DB": degrees, centimetres) and ROS velodyne YAML
// (radians, metres) calibrations, parsed with tinyxml2 and yaml-cpp.
#include "socc/sensors/velodyne_calibration.hpp"

#include <tinyxml2.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>

namespace socc::sensors::velodyne {
namespace {

constexpr double kDegToRad = M_PI / 180.0;
constexpr double kCmToM = 0.01;

[[noreturn]] void failCalibration(const std::filesystem::path& file, const std::string& why) {
  throw std::runtime_error(file.string() + ": " + why);
}

double xmlNumber(const tinyxml2::XMLElement* parent, const char* name,
                 const std::filesystem::path& file, int id) {
  const tinyxml2::XMLElement* e = parent->FirstChildElement(name);
  if (e == nullptr) return 0.0;  // VeloView omits nothing, older files may
  double v = 0.0;
  if (e->QueryDoubleText(&v) != tinyxml2::XML_SUCCESS || !std::isfinite(v))
    failCalibration(file, "laser " + std::to_string(id) + ": <" + name + "> is not a number");
  return v;
}

std::vector<bool> xmlEnabled(const tinyxml2::XMLElement* db) {
  std::vector<bool> enabled;
  const tinyxml2::XMLElement* list = db->FirstChildElement("enabled_");
  if (list == nullptr) return enabled;
  for (const tinyxml2::XMLElement* it = list->FirstChildElement("item"); it != nullptr;
       it = it->NextSiblingElement("item")) {
    int v = 1;
    it->QueryIntText(&v);
    enabled.push_back(v != 0);
  }
  return enabled;
}

Calibration loadXml(const std::filesystem::path& file) {
  tinyxml2::XMLDocument doc;
  if (doc.LoadFile(file.c_str()) != tinyxml2::XML_SUCCESS)
    failCalibration(file, std::string("not a readable XML file (") + doc.ErrorStr() + ")");
  const tinyxml2::XMLElement* root = doc.FirstChildElement("boost_serialization");
  const tinyxml2::XMLElement* db = root ? root->FirstChildElement("DB") : nullptr;
  const tinyxml2::XMLElement* points = db ? db->FirstChildElement("points_") : nullptr;
  if (points == nullptr)
    failCalibration(file, "not a VeloView calibration (no DB/points_ element)");
  Calibration cal;
  if (const tinyxml2::XMLElement* lsb = db->FirstChildElement("distLSB_")) {
    double cm = 0.0;
    if (lsb->QueryDoubleText(&cm) != tinyxml2::XML_SUCCESS || !(cm > 0.0) || cm > 10.0)
      failCalibration(file, "distLSB_ is not a distance resolution in cm");
    cal.distance_resolution_m = cm * kCmToM;
  }
  const std::vector<bool> enabled = xmlEnabled(db);
  std::map<int, LaserCalibration> by_id;
  for (const tinyxml2::XMLElement* item = points->FirstChildElement("item"); item != nullptr;
       item = item->NextSiblingElement("item")) {
    const tinyxml2::XMLElement* px = item->FirstChildElement("px");
    if (px == nullptr) failCalibration(file, "points_ item without px");
    int id = -1;
    const tinyxml2::XMLElement* id_e = px->FirstChildElement("id_");
    if (id_e == nullptr || id_e->QueryIntText(&id) != tinyxml2::XML_SUCCESS || id < 0 || id > 255)
      failCalibration(file, "laser without a valid id_");
    LaserCalibration l;
    l.rot_rad = xmlNumber(px, "rotCorrection_", file, id) * kDegToRad;
    l.vert_rad = xmlNumber(px, "vertCorrection_", file, id) * kDegToRad;
    l.dist_m = xmlNumber(px, "distCorrection_", file, id) * kCmToM;
    l.dist_x_m = xmlNumber(px, "distCorrectionX_", file, id) * kCmToM;
    l.dist_y_m = xmlNumber(px, "distCorrectionY_", file, id) * kCmToM;
    l.vert_offset_m = xmlNumber(px, "vertOffsetCorrection_", file, id) * kCmToM;
    l.horiz_offset_m = xmlNumber(px, "horizOffsetCorrection_", file, id) * kCmToM;
    l.focal_distance_m = xmlNumber(px, "focalDistance_", file, id) * kCmToM;
    l.focal_slope = xmlNumber(px, "focalSlope_", file, id);
    l.enabled =
        static_cast<std::size_t>(id) >= enabled.size() || enabled[static_cast<std::size_t>(id)];
    if (!by_id.emplace(id, l).second)
      failCalibration(file, "laser id " + std::to_string(id) + " twice");
  }
  for (auto& [id, l] : by_id) cal.lasers.push_back(l);
  if (!by_id.empty() && by_id.rbegin()->first + 1 != static_cast<int>(by_id.size()))
    failCalibration(file, "laser ids are not 0.." + std::to_string(by_id.size() - 1));
  return cal;
}

double yamlNumber(const YAML::Node& laser, const char* key, const std::filesystem::path& file,
                  int id) {
  const YAML::Node v = laser[key];
  if (!v) return 0.0;
  double d = 0.0;
  try {
    d = v.as<double>();
  } catch (const YAML::Exception&) {
    failCalibration(file, "laser " + std::to_string(id) + ": " + key + " is not a number");
  }
  if (!std::isfinite(d))
    failCalibration(file, "laser " + std::to_string(id) + ": " + key + " is not finite");
  return d;
}

Calibration loadYaml(const std::filesystem::path& file) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(file.string());
  } catch (const YAML::Exception& e) {
    failCalibration(file, std::string("not a readable YAML file (") + e.what() + ")");
  }
  if (!root.IsMap() || !root["lasers"] || !root["lasers"].IsSequence())
    failCalibration(file, "not a ROS velodyne calibration (no 'lasers' list)");
  Calibration cal;
  if (root["distance_resolution"]) {
    try {
      cal.distance_resolution_m = root["distance_resolution"].as<double>();
    } catch (const YAML::Exception&) {
      failCalibration(file, "distance_resolution is not a number");
    }
    if (!(cal.distance_resolution_m > 0.0) || cal.distance_resolution_m > 0.1)
      failCalibration(file, "distance_resolution is not a resolution in metres");
  }
  std::map<int, LaserCalibration> by_id;
  for (const YAML::Node& laser : root["lasers"]) {
    if (!laser.IsMap() || !laser["laser_id"]) failCalibration(file, "a laser without laser_id");
    const double id_d = yamlNumber(laser, "laser_id", file, -1);
    const int id = static_cast<int>(id_d);
    if (id_d != id || id < 0 || id > 255) failCalibration(file, "laser_id is not an id 0..255");
    LaserCalibration l;
    l.rot_rad = yamlNumber(laser, "rot_correction", file, id);
    l.vert_rad = yamlNumber(laser, "vert_correction", file, id);
    l.dist_m = yamlNumber(laser, "dist_correction", file, id);
    l.dist_x_m = yamlNumber(laser, "dist_correction_x", file, id);
    l.dist_y_m = yamlNumber(laser, "dist_correction_y", file, id);
    l.vert_offset_m = yamlNumber(laser, "vert_offset_correction", file, id);
    l.horiz_offset_m = yamlNumber(laser, "horiz_offset_correction", file, id);
    l.focal_distance_m = yamlNumber(laser, "focal_distance", file, id);
    l.focal_slope = yamlNumber(laser, "focal_slope", file, id);
    if (!by_id.emplace(id, l).second)
      failCalibration(file, "laser id " + std::to_string(id) + " twice");
  }
  for (auto& [id, l] : by_id) cal.lasers.push_back(l);
  if (!by_id.empty() && by_id.rbegin()->first + 1 != static_cast<int>(by_id.size()))
    failCalibration(file, "laser ids are not 0.." + std::to_string(by_id.size() - 1));
  if (root["num_lasers"]) {
    const double n = yamlNumber(root, "num_lasers", file, -1);
    if (n != static_cast<double>(cal.lasers.size()))
      failCalibration(file, "num_lasers says " + std::to_string(static_cast<int>(n)) + " but " +
                                std::to_string(cal.lasers.size()) + " lasers are listed");
  }
  return cal;
}

void checkRanges(const std::filesystem::path& file, const Calibration& cal) {
  if (cal.lasers.empty()) failCalibration(file, "no lasers");
  for (std::size_t i = 0; i < cal.lasers.size(); ++i) {
    const LaserCalibration& l = cal.lasers[i];
    const bool sane = std::abs(l.vert_rad) <= 45.0 * kDegToRad &&
                      std::abs(l.rot_rad) <= 45.0 * kDegToRad && std::abs(l.dist_m) <= 5.0 &&
                      std::abs(l.dist_x_m) <= 5.0 && std::abs(l.dist_y_m) <= 5.0 &&
                      std::abs(l.vert_offset_m) <= 1.0 && std::abs(l.horiz_offset_m) <= 1.0;
    if (!sane)
      failCalibration(
          file, "laser " + std::to_string(i) +
                    ": angles or offsets out of range (degrees given as radians, or cm as m?)");
  }
}

std::string lowerExtension(const std::filesystem::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext;
}

}  // namespace

Calibration loadCalibration(const std::filesystem::path& file) {
  if (!std::filesystem::is_regular_file(file)) failCalibration(file, "no such calibration file");
  const std::string ext = lowerExtension(file);
  Calibration cal;
  if (ext == ".xml")
    cal = loadXml(file);
  else if (ext == ".yaml" || ext == ".yml")
    cal = loadYaml(file);
  else
    failCalibration(file,
                    "unknown calibration format (VeloView .xml or ROS velodyne .yaml expected)");
  checkRanges(file, cal);
  return cal;
}

}  // namespace socc::sensors::velodyne
