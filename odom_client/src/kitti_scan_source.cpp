// KITTI-layout directory scan source.
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "socc/gravity_file.hpp"
#include "socc/kitti_io.hpp"
#include "socc/labels.hpp"
#include "socc/odom/scan_source.hpp"

namespace socc::odom {
namespace fs = std::filesystem;
namespace {

class KittiDirectorySource final : public ScanSource {
 public:
  KittiDirectorySource(const fs::path& root, FrameRange range, double frame_period)
      : sequence_(listKittiSequence(root)), frame_period_(frame_period) {
    if (sequence_.scans.empty())
      throw std::runtime_error(root.string() + ": no velodyne/*.bin scans");
    const fs::path times = root / "times.txt";
    if (fs::exists(times)) {
      times_ = readTimes(times);
      if (times_.size() < sequence_.scans.size())
        throw std::runtime_error(times.string() + ": fewer times than scans");
    }
    const fs::path gravity = root / "gravity.txt";
    if (fs::exists(gravity)) {
      gravity_ = readGravityFile(gravity);
      if (gravity_.size() < sequence_.scans.size())
        throw std::runtime_error(gravity.string() + ": " + std::to_string(gravity_.size()) +
                                 " lines for " + std::to_string(sequence_.scans.size()) +
                                 " scans (one line per velodyne/ scan)");
    }
    const auto n = static_cast<std::int64_t>(sequence_.scans.size());
    if (range.first < 0 || range.first >= n)
      throw std::runtime_error(root.string() + ": first frame " + std::to_string(range.first) +
                               " is outside 0.." + std::to_string(n - 1));
    next_ = range.first;
    end_ = range.last < 0 ? n : std::min(n, range.last + 1);
  }

  std::optional<Scan> next() override {
    if (next_ >= end_) return std::nullopt;
    const auto i = static_cast<std::size_t>(next_);
    Scan scan;
    scan.seq = next_++;
    scan.name = sequence_.scans[i].filename().string();
    scan.cloud.points = readKittiBin(sequence_.scans[i]);
    if (!sequence_.labels[i].empty()) {
      const std::vector<std::uint32_t> raw = readSemanticKittiLabels(sequence_.labels[i]);
      if (raw.size() != scan.cloud.size())
        throw std::runtime_error(sequence_.labels[i].string() + ": " + std::to_string(raw.size()) +
                                 " labels for " + std::to_string(scan.cloud.size()) + " points");
      scan.cloud.labels.reserve(raw.size());
      for (const std::uint32_t l : raw)
        scan.cloud.labels.push_back(mapSemanticKittiLabel(l & 0xFFFFu));
    }
    char name[32];
    std::snprintf(name, sizeof(name), "%06zu.bin", i);
    const fs::path point_times = sequence_.root / "point_times" / name;
    if (fs::exists(point_times)) {
      scan.cloud.times = readFloatBin(point_times);
      if (scan.cloud.times.size() != scan.cloud.size())
        throw std::runtime_error(point_times.string() + ": " +
                                 std::to_string(scan.cloud.times.size()) + " times for " +
                                 std::to_string(scan.cloud.size()) + " points");
    }
    scan.utime = times_.empty() ? std::llround(static_cast<double>(i) * frame_period_ * 1e6)
                                : static_cast<std::int64_t>(times_[i] * 1e6);
    if (!gravity_.empty()) scan.gravity = gravity_[i];
    return scan;
  }

  std::size_t remaining() const override { return static_cast<std::size_t>(end_ - next_); }

  std::string timing() const override {
    if (!times_.empty()) return "times.txt";
    return "none (no times.txt): assuming " + std::to_string(frame_period_) +
           " s between scans (frame_period; set it with --frame-period)";
  }

 private:
  KittiSequence sequence_;
  double frame_period_;
  std::vector<double> times_;
  std::vector<std::optional<GravityReference>> gravity_;  // empty: no gravity.txt
  std::int64_t next_ = 0;
  std::int64_t end_ = 0;
};

}  // namespace

std::unique_ptr<ScanSource> openKittiDirectory(const fs::path& root, FrameRange range,
                                               double frame_period) {
  return std::make_unique<KittiDirectorySource>(root, range, frame_period);
}

}  // namespace socc::odom
