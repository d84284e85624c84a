// Directory of PCD / PLY files as a scan source.
#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "socc/odom/file_name_stamps.hpp"
#include "socc/odom/point_cloud_file.hpp"
#include "socc/odom/scan_source.hpp"

namespace socc::odom {
namespace fs = std::filesystem;
namespace {

class PointCloudDirectorySource final : public ScanSource {
 public:
  PointCloudDirectorySource(const fs::path& dir, FrameRange range, double frame_period)
      : frame_period_(frame_period) {
    if (!fs::is_directory(dir)) throw std::runtime_error(dir.string() + ": not a directory");
    for (const auto& entry : fs::directory_iterator(dir))
      if (entry.is_regular_file() && isPointCloudFile(entry.path())) files_.push_back(entry.path());
    std::sort(files_.begin(), files_.end());
    if (files_.empty()) throw std::runtime_error(dir.string() + ": no .pcd or .ply files");
    const auto n = static_cast<std::int64_t>(files_.size());
    if (range.first < 0 || range.first >= n)
      throw std::runtime_error(dir.string() + ": first frame " + std::to_string(range.first) +
                               " is outside 0.." + std::to_string(n - 1));
    next_ = range.first;
    end_ = range.last < 0 ? n : std::min(n, range.last + 1);
    stamps_ = fileNameStamps(files_);
  }

  std::optional<Scan> next() override {
    if (next_ >= end_) return std::nullopt;
    Scan scan;
    scan.seq = next_;
    scan.name = files_[static_cast<std::size_t>(next_)].filename().string();
    scan.cloud = loadPointCloudFile(files_[static_cast<std::size_t>(next_)]);
    scan.utime = stamps_.empty() ? std::llround(static_cast<double>(next_) * frame_period_ * 1e6)
                                 : stamps_[static_cast<std::size_t>(next_)];
    ++next_;
    return scan;
  }

  std::size_t remaining() const override { return static_cast<std::size_t>(end_ - next_); }

  std::string timing() const override {
    std::ostringstream out;
    if (!stamps_.empty()) {
      out << "from the file names (" << files_.front().filename().string() << " ... "
          << files_.back().filename().string() << ")";
    } else {
      out << "none in the file names: assuming " << frame_period_
          << " s between scans (frame_period; set it with --frame-period)";
    }
    return out.str();
  }

 private:
  std::vector<fs::path> files_;
  std::vector<std::int64_t> stamps_;  // [us] from the file names; empty: none
  double frame_period_;
  std::int64_t next_ = 0;
  std::int64_t end_ = 0;
};

}  // namespace

std::unique_ptr<ScanSource> openPointCloudDirectory(const fs::path& dir, FrameRange range,
                                                    double frame_period) {
  return std::make_unique<PointCloudDirectorySource>(dir, range, frame_period);
}

}  // namespace socc::odom
