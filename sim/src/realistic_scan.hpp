#pragma once
// One sweep with the realism error models (socc/sim/realism.hpp); scan_simulator.cpp calls it
// when any scan error is switched on, and keeps its exact path otherwise.
#include "socc/sim/scan_simulator.hpp"

namespace socc::sim {

SimulatedScan simulateRealisticScan(const Scene& scene, const LidarModel& model, double sweep_start,
                                    std::uint64_t frame, const ScanOptions& options);

}  // namespace socc::sim
