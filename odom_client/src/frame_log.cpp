#include "socc/odom/frame_log.hpp"

#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace socc::odom {

FrameLog::FrameLog(const std::filesystem::path& csv_file) {
  if (csv_file.empty()) return;
  csv_.open(csv_file, std::ios::trunc);
  if (!csv_) throw std::runtime_error(csv_file.string() + ": cannot open for writing");
  csv_ << "frame,preprocess_ms,fetch_ms,map_build_ms,chunk_ms,register_ms,integrate_ms,wait_ms,"
          "total_ms,corr_planar,"
          "corr_non_planar,alpha,iterations,chunk_voxels,bytes_received,bytes_sent,sigma,points,"
          "downsampled_points,deskew_passes,status,inlier_fraction,residual_ratio,weakest_"
          "constraint,"
          "speed,integrated,problem,surprise\n";
}

void FrameLog::add(const FrameStats& s) {
  ++frames_;
  rows_.push_back(s);
  sum_.preprocess_ms += s.preprocess_ms;
  sum_.fetch_ms += s.fetch_ms;
  sum_.map_build_ms += s.map_build_ms;
  sum_.chunk_ms += s.chunk_ms;
  sum_.register_ms += s.register_ms;
  sum_.integrate_ms += s.integrate_ms;
  sum_.wait_ms += s.wait_ms;
  sum_.total_ms += s.total_ms;
  sum_.planar += s.planar;
  sum_.non_planar += s.non_planar;
  sum_.alpha += s.alpha;
  sum_.iterations += s.iterations;
  sum_.chunk_voxels += s.chunk_voxels;
  sum_.bytes_received += s.bytes_received;
  sum_.bytes_sent += s.bytes_sent;
  sum_.sigma += s.sigma;
  sum_.points += s.points;
  sum_.downsampled_points += s.downsampled_points;
  if (!csv_.is_open()) return;
  csv_ << s.frame << std::fixed << std::setprecision(3) << ',' << s.preprocess_ms << ','
       << s.fetch_ms << ',' << s.map_build_ms << ',' << s.chunk_ms << ',' << s.register_ms << ','
       << s.integrate_ms << ',' << s.wait_ms << ',' << s.total_ms << ',' << s.planar << ','
       << s.non_planar << ',' << std::setprecision(4) << s.alpha << ',' << s.iterations << ','
       << s.chunk_voxels << ',' << s.bytes_received << ',' << s.bytes_sent << ','
       << std::setprecision(4) << s.sigma << ',' << s.points << ',' << s.downsampled_points << ','
       << s.deskew_passes << ',' << s.status << ',' << s.inlier_fraction << ',' << s.residual_ratio
       << ',' << s.weakest_constraint << ',' << s.speed << ',' << (s.integrated ? 1 : 0) << ",\""
       << s.problem << "\",\"" << s.surprise << "\"\n";
  csv_.flush();  // a killed client still leaves a complete log
}

std::int64_t FrameLog::count(const std::string& status) const {
  std::int64_t n = 0;
  for (const FrameStats& s : rows_) n += s.status == status ? 1 : 0;
  return n;
}

FrameStats FrameLog::mean() const {
  FrameStats m;
  if (frames_ == 0) return m;
  const double n = static_cast<double>(frames_);
  m.preprocess_ms = sum_.preprocess_ms / n;
  m.fetch_ms = sum_.fetch_ms / n;
  m.map_build_ms = sum_.map_build_ms / n;
  m.chunk_ms = sum_.chunk_ms / n;
  m.register_ms = sum_.register_ms / n;
  m.integrate_ms = sum_.integrate_ms / n;
  m.wait_ms = sum_.wait_ms / n;
  m.total_ms = sum_.total_ms / n;
  m.planar = static_cast<int>(sum_.planar / n);
  m.non_planar = static_cast<int>(sum_.non_planar / n);
  m.alpha = sum_.alpha / n;
  m.iterations = static_cast<int>(sum_.iterations / n);
  m.chunk_voxels = static_cast<std::int64_t>(static_cast<double>(sum_.chunk_voxels) / n);
  m.bytes_received = static_cast<std::int64_t>(static_cast<double>(sum_.bytes_received) / n);
  m.bytes_sent = static_cast<std::int64_t>(static_cast<double>(sum_.bytes_sent) / n);
  m.sigma = sum_.sigma / n;
  m.points = static_cast<std::int64_t>(static_cast<double>(sum_.points) / n);
  m.downsampled_points =
      static_cast<std::int64_t>(static_cast<double>(sum_.downsampled_points) / n);
  return m;
}

std::string FrameLog::summary(double wall_seconds) const {
  const FrameStats m = mean();
  std::ostringstream out;
  out << std::fixed << std::setprecision(2) << "frames: " << frames_ << "\n"
      << "mean ms/frame: preprocess " << m.preprocess_ms << ", fetch " << m.fetch_ms
      << " (of which map build " << m.map_build_ms << "), register " << m.register_ms
      << ", wait for the previous frame " << m.wait_ms << ", total " << m.total_ms << "\n"
      << "round trips (in the worker thread): GET_CHUNK " << m.chunk_ms << ", INTEGRATE "
      << m.integrate_ms << "\n"
      << "rate: " << (wall_seconds > 0.0 ? frames_ / wall_seconds : 0.0) << " Hz over "
      << wall_seconds << " s\n"
      << "chunk: " << m.chunk_voxels << " voxels, " << m.bytes_received / 1024.0
      << " KiB/frame received, Integrate " << m.bytes_sent / 1024.0
      << " KiB/frame sent; registered points " << m.downsampled_points << " of " << m.points
      << "; iterations " << m.iterations << "; alpha " << m.alpha << "\n"
      << "health: " << count("ok") << " ok, " << count("degenerate") << " degenerate, "
      << count("retried") << " retried, " << count("unhealthy") << " unhealthy, " << count("lost")
      << " lost";
  if (const std::int64_t own = count("own_frame"); own > 0)
    out << ", " << own << " in its own frame (--own-frame, before the merge)";
  out << "\n";
  return out.str();
}

}  // namespace socc::odom
