// The one factory of packet decoders: one line per vendor family in kFamilies.
#include <algorithm>
#include <stdexcept>

#include "detecting_decoder.hpp"
#include "sender_selection.hpp"
#include "socc/sensors/hesai_decoder.hpp"
#include "socc/sensors/ouster_decoder.hpp"
#include "socc/sensors/sensor_config.hpp"
#include "velodyne/velodyne_decoder.hpp"
#include "velodyne/velodyne_model.hpp"

namespace socc::sensors {
namespace {

struct Family {
  std::vector<std::string> (*models)();  // the names listed in --help and errors
  bool (*accepts)(const std::string&);   // also the names a family derives (os1-64, os0-128...)
  std::unique_ptr<ScanDecoder> (*make)(const SensorConfig&);
};

std::vector<std::string> velodyneModelNames() {
  std::vector<std::string> names;
  for (const velodyne::ModelInfo& m : velodyne::velodyneModels()) names.emplace_back(m.name);
  return names;
}

bool isVelodyneModel(const std::string& model) {
  const std::vector<std::string> names = velodyneModelNames();
  return std::find(names.begin(), names.end(), model) != names.end();
}

// Ouster models follow from the metadata JSON (os<family>-<beams>); these are the common ones.
std::vector<std::string> ousterModelNames() {
  return {"os0-32",  "os0-64", "os0-128", "os1-16",  "os1-32", "os1-64",
          "os1-128", "os2-32", "os2-64",  "os2-128", "ouster"};
}

const Family kFamilies[] = {
    {velodyneModelNames, isVelodyneModel, velodyne::makeVelodyneDecoder},
    {ousterModelNames, isOusterModel, makeOusterDecoder},
    {hesaiModels, isHesaiModel, makeHesaiDecoder},
};

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

// The decoder of config's model (or the detecting one), without the sender selection.
std::unique_ptr<ScanDecoder> makeModelDecoder(const SensorConfig& config) {
  if (config.model.empty()) return makeDetectingDecoder(config);
  for (const Family& f : kFamilies)
    if (f.accepts(config.model)) return f.make(config);
  throw std::runtime_error("unknown sensor model '" + config.model +
                           "' (known: " + joined(supportedModels()) + ")");
}

}  // namespace

std::unique_ptr<ScanDecoder> makeDecoder(const SensorConfig& config) {
  return selectSender(config, makeModelDecoder(config));
}

std::vector<std::string> supportedModels() {
  std::vector<std::string> all;
  for (const Family& f : kFamilies)
    for (std::string& n : f.models()) all.push_back(std::move(n));
  return all;
}

}  // namespace socc::sensors
