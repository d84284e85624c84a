#pragma once
// Per-frame statistics: one CSV row per frame and the end-of-run summary.
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace socc::odom {

/// Milliseconds since t: the unit of FrameStats' timings.
inline double msSince(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

struct FrameStats {
  std::int64_t frame = 0;      // sequence number
  double preprocess_ms = 0.0;  // read + range filter + deskew + downsampling
  double fetch_ms = 0.0;       // the frame waited for its registration target (map_pipeline.hpp)
  double map_build_ms = 0.0;   // of fetch_ms: decoding the chunk and building search trees
  double chunk_ms = 0.0;       // GET_CHUNK round trip + decoding of the target's chunk (in the
                               // worker thread when pipelined, else part of fetch_ms)
  double register_ms = 0.0;
  double integrate_ms = 0.0;  // Integrate round trip (in the worker thread)
  double wait_ms = 0.0;       // the frame waited for the previous frame's Integrate (and chunk)
                              // before its own Integrate went out
  double total_ms = 0.0;      // wall time of the frame in the pipeline, wait_ms included
  int planar = 0;
  int non_planar = 0;
  double alpha = 0.0;
  int iterations = 0;
  std::int64_t chunk_voxels = 0;
  std::int64_t bytes_received = 0;  // encoded chunk reply
  std::int64_t bytes_sent = 0;      // encoded Integrate request
  double sigma = 0.0;
  std::int64_t points = 0;              // range-filtered (integrated) points
  std::int64_t downsampled_points = 0;  // registered points
  int deskew_passes = 0;
  // Health (odom_client/README.md "Health"): status is "ok", "degenerate", "retried",
  // "unhealthy" (not integrated), "lost" (not integrated; the robot lost track), "relocalizing"
  // (searching its pose in the map), "refused" (the server refused it as implausible) or
  // "own_frame" (--own-frame before the merge: registered in the robot's own frame, not
  // integrated then; its pose in the trajectory files is moved into the map frame at the merge).
  std::string status = "ok";
  std::string problem;   // why the frame is unhealthy
  std::string surprise;  // a kinematic limit exceeded (FrameHealth::surprise; reported only)
  double inlier_fraction = 0.0;
  double residual_ratio = 0.0;
  double weakest_constraint = 0.0;  // FrameHealth::weakest_constraint
  double speed = 0.0;               // [m/s]
  bool integrated = false;
};

/// Writes frames.csv (when a path is given) and accumulates the means for the summary.
class FrameLog {
 public:
  explicit FrameLog(const std::filesystem::path& csv_file = {});
  void add(const FrameStats& s);
  std::int64_t frames() const { return frames_; }
  /// Frames whose status is `status`.
  std::int64_t count(const std::string& status) const;
  /// Human-readable summary: frames, mean ms per stage, Hz, bytes/frame.
  std::string summary(double wall_seconds) const;
  FrameStats mean() const;
  const std::vector<FrameStats>& rows() const { return rows_; }

 private:
  std::ofstream csv_;
  std::int64_t frames_ = 0;
  FrameStats sum_;
  std::vector<FrameStats> rows_;
};

}  // namespace socc::odom
