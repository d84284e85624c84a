#pragma once
// The rooms behind a building's windows. A pulse that passes a window travels on into a room and
// returns from the first wall, floor or ceiling it meets. Rooms are bounded boxes inside the
// building, fixed in the world: every viewpoint sees the same interior surfaces, and a ray that
// crosses the window at a steep angle meets the room's side wall (perpendicular to the facade)
// instead of running on for metres along an unbounded back wall.
#include <optional>

#include "socc/sim/primitives.hpp"

namespace socc::sim {

/// Interior layout (sim/README.md "Realism": the figures and their sources).
struct RoomLayout {
  double depth = 3.0;   // [m] facade to back wall
  double width = 4.0;   // [m] side wall to side wall, along the facade from the building's end
  double storey = 3.0;  // [m] floor to floor, from the building's base
  double grazing_cosine = 0.3;  // below this incidence cosine glass reflects the pulse away
};

/// Distance the pulse travels inside `building` after entering a window at `range` along `ray`:
/// to the nearest wall, floor or ceiling of the room it enters. None when the glass reflects the
/// pulse away (grazing incidence) or the ray meets the roof (no windows there).
std::optional<double> roomTravel(const Ray& ray, double range, const Box& building,
                                 const RoomLayout& rooms);

}  // namespace socc::sim
