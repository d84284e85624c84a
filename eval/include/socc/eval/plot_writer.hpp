#pragma once
// PNG plots of an evaluation: writes plain data files into a directory and renders them with
// gnuplot scripts (scripts/plot_*.gp), so the plots can be re-made or restyled from the data.
#include <filesystem>

#include "socc/eval/evaluation.hpp"

namespace socc::eval {

/// Writes trajectory.dat, errors.dat, kitti_lengths.dat and kitti_speeds.dat into dir (created
/// if needed).
void writePlotData(const std::filesystem::path& dir, const Poses& gt, const Poses& est,
                   const Evaluation& e);

/// Runs gnuplot on plot_trajectory.gp, plot_errors.gp (and plot_kitti_lengths.gp,
/// plot_kitti_speeds.gp when KITTI metrics exist) from script_dir, writing trajectory.png,
/// errors.png, kitti_lengths.png, kitti_speeds.png.
/// Throws std::runtime_error when a script is missing or gnuplot fails.
void renderPlots(const std::filesystem::path& dir, const std::filesystem::path& script_dir,
                 const Evaluation& e);

}  // namespace socc::eval
