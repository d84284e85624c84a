#include "socc/tools/scan_directory.hpp"

#include <algorithm>
#include <cctype>
#include <limits>
#include <stdexcept>
#include <string>

#include "socc/kitti_io.hpp"
#include "socc/labels.hpp"

namespace socc::tools {
namespace fs = std::filesystem;

namespace {

[[noreturn]] void fail(const fs::path& where, const std::string& why) {
  throw std::runtime_error(where.string() + ": " + why);
}

bool isFrameNumber(const std::string& stem) {
  return !stem.empty() && stem.size() <= 9 &&
         std::all_of(stem.begin(), stem.end(), [](unsigned char c) { return std::isdigit(c); });
}

std::vector<fs::path> listPcdFiles(const fs::path& root) {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(root))
    if (e.is_regular_file() && e.path().extension() == ".pcd") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

// KITTI's times.txt has one line per frame of the whole sequence, so a numbered scan takes
// the line of its frame number (directories may hold a slice); other names go by position.
std::vector<double> scanTimes(const fs::path& times_file, const std::vector<fs::path>& scans) {
  const std::vector<double> times = readTimes(times_file);
  const bool numbered = std::all_of(scans.begin(), scans.end(), [](const fs::path& p) {
    return isFrameNumber(p.stem().string());
  });
  std::vector<double> out;
  out.reserve(scans.size());
  for (std::size_t i = 0; i < scans.size(); ++i) {
    const std::size_t line = numbered ? std::stoul(scans[i].stem().string()) : i;
    if (line >= times.size())
      fail(times_file, "has " + std::to_string(times.size()) + " times, none for scan " +
                           scans[i].filename().string());
    out.push_back(times[line]);
  }
  return out;
}

void checkCount(const fs::path& file, std::size_t count, std::size_t points, const char* what) {
  if (count != points)
    fail(file, std::to_string(count) + " " + what + " for " + std::to_string(points) + " points");
}

}  // namespace

ScanDirectory openScanDirectory(const fs::path& root) {
  if (!fs::is_directory(root)) fail(root, "not a directory");
  ScanDirectory dir;
  dir.root = root;
  if (fs::is_directory(root / "velodyne")) {
    KittiSequence seq = listKittiSequence(root);
    dir.format = ScanFormat::kKitti;
    dir.scans = std::move(seq.scans);
    dir.labels = std::move(seq.labels);
    for (const auto& s : dir.scans) {
      const fs::path t = root / "point_times" / s.filename();
      dir.point_times.push_back(fs::exists(t) ? t : fs::path());
    }
  } else {
    dir.format = ScanFormat::kPcd;
    dir.scans = listPcdFiles(root);
    if (dir.scans.empty()) fail(root, "neither a velodyne/ directory (KITTI) nor *.pcd files");
    dir.labels.assign(dir.scans.size(), fs::path());
    dir.point_times.assign(dir.scans.size(), fs::path());
  }
  if (fs::exists(root / "times.txt")) dir.scan_times = scanTimes(root / "times.txt", dir.scans);
  return dir;
}

ScanFrame loadScan(const ScanDirectory& dir, std::size_t i) {
  if (i >= dir.scans.size()) throw std::out_of_range("scan index out of range");
  const fs::path& file = dir.scans[i];
  ScanFrame frame;
  if (dir.format == ScanFormat::kPcd) {
    frame = readPcdScan(file);
  } else {
    frame.cloud.points = readKittiBin(file, &frame.intensity);
    if (!dir.labels[i].empty()) {
      const std::vector<std::uint32_t> raw = readSemanticKittiLabels(dir.labels[i]);
      checkCount(dir.labels[i], raw.size(), frame.cloud.size(), "labels");
      frame.cloud.labels.reserve(raw.size());
      for (const std::uint32_t r : raw) frame.cloud.labels.push_back(mapSemanticKittiLabel(r));
    }
    if (!dir.point_times[i].empty()) {
      frame.cloud.times = readFloatBin(dir.point_times[i]);
      checkCount(dir.point_times[i], frame.cloud.times.size(), frame.cloud.size(), "times");
    }
  }
  // scan_t counts are int32.
  if (frame.cloud.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
    fail(file, "too many points for one scan_t");
  return frame;
}

}  // namespace socc::tools
