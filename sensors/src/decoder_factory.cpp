// The one factory of packet decoders: one line per vendor family in kFamilies.
#include <algorithm>
#include <stdexcept>

#include "socc/sensors/sensor_config.hpp"
#include "velodyne/velodyne_decoder.hpp"
#include "velodyne/velodyne_model.hpp"

namespace socc::sensors {
namespace {

struct Family {
  std::vector<std::string> (*models)();
  std::unique_ptr<ScanDecoder> (*make)(const SensorConfig&);
};

std::vector<std::string> velodyneModelNames() {
  std::vector<std::string> names;
  for (const velodyne::ModelInfo& m : velodyne::velodyneModels()) names.emplace_back(m.name);
  return names;
}

// An empty model name goes to the first family (Velodyne), which detects its model.
const Family kFamilies[] = {
    {velodyneModelNames, velodyne::makeVelodyneDecoder},
};

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

}  // namespace

std::unique_ptr<ScanDecoder> makeDecoder(const SensorConfig& config) {
  if (config.model.empty()) return kFamilies[0].make(config);
  for (const Family& f : kFamilies) {
    const std::vector<std::string> names = f.models();
    if (std::find(names.begin(), names.end(), config.model) != names.end()) return f.make(config);
  }
  throw std::runtime_error("unknown sensor model '" + config.model +
                           "' (known: " + joined(supportedModels()) + ")");
}

std::vector<std::string> supportedModels() {
  std::vector<std::string> all;
  for (const Family& f : kFamilies)
    for (std::string& n : f.models()) all.push_back(std::move(n));
  return all;
}

}  // namespace socc::sensors
