#pragma once
// World builders per scene type (internal to socc_sim). Each builds around a route whose points
// are sensor positions; the ground lies sensor_height below them.
#include <memory>

#include "socc/sim/random.hpp"
#include "socc/sim/world.hpp"

namespace socc::sim {

World buildStreetWorld(const std::shared_ptr<const Path>& route, double sensor_height, Random& rng);
World buildCorridorWorld(const Path& route, double sensor_height);
World buildOfficeWorld(const Path& route, double sensor_height, Random& rng);
World buildIndoorWorld(const Path& route, double sensor_height, Random& rng);

}  // namespace socc::sim
