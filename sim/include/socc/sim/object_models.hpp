#pragma once
// Street furniture and agents built from primitives, in an object frame: x forward, z up,
// origin on the ground under the object's centre.
#include <cstdint>
#include <vector>

#include "socc/sim/primitives.hpp"
#include "socc/sim/random.hpp"

namespace socc::sim {

using Parts = std::vector<Primitive>;

Parts carModel(std::uint16_t label);     // 4.3 x 1.8 m body with a cabin
Parts personModel(std::uint16_t label);  // cylinder body and a spherical head
/// Trunk and a crown of randomly placed overlapping spheres (a non-planar, bumpy surface).
Parts treeModel(Random& rng);
Parts streetLampModel();
Parts trafficSignModel();  // the sign plate faces along +x

/// Moves object-frame parts to a ground position with a heading (parts keep their labels).
Parts placeParts(const Parts& parts, const Eigen::Vector3d& ground, double heading);

}  // namespace socc::sim
