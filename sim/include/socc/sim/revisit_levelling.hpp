#pragma once
// Recorded routes whose heights do not close. KITTI's ground truth (GPS/INS) drifts in height:
// where a drive comes back to a place it drove before, its second pass is recorded up to 6 m
// above or below the first (00: 1.1 m, 02: 4.4 m, 08: 6.4 m, 09: 3.2 m; docs/simulator.md
// "Revisits at one height"). A world built at those heights has two road slabs there, a place
// no real drive comes back to. levelRevisits spreads each revisit's height difference along the
// drive between its passes, as a pose graph spreads a loop's error: a height correction along
// the path, zero at the first pose, that brings the passes of every revisit to one height at the
// least cost of a random walk of the recorded heights and of sharp bends of the levelled road
// (so the pass whose recorded heights jump is the one that moves). Only heights change: the
// recorded attitude, an INS's, is far better than its GPS heights.
#include <cstddef>

#include "socc/kitti_io.hpp"

namespace socc::sim {

struct RevisitLevelling {
  double radius = 4.0;          // [m] horizontally: two passes of one place (lanes apart)
  double min_path = 50.0;       // [m] of drive between two passes of one place
  double revisit_sigma = 0.02;  // [m] how closely the passes must agree
  double drift_sigma = 0.01;    // [m / sqrt(m)] the recorded heights' random walk
  double bend_sigma = 0.001;    // [1/m] how fast the levelled road's grade may change
};

struct LevelledRoute {
  Poses poses;
  std::size_t revisit_pairs = 0;  // poses tied to an earlier pass
  double max_change = 0.0;        // [m] the largest height correction
};

/// poses (sensor poses, +z up) with their heights levelled at revisits (any angle: a route over
/// a bridge across its own earlier path needs its recorded heights); unchanged without one.
LevelledRoute levelRevisits(const Poses& poses, const RevisitLevelling& params = {});

}  // namespace socc::sim
