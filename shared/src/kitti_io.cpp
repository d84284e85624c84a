#include "socc/kitti_io.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace socc {
namespace fs = std::filesystem;

namespace {

[[noreturn]] void fail(const fs::path& file, const std::string& why) {
  throw std::runtime_error(file.string() + ": " + why);
}

std::vector<char> readAll(const fs::path& file) {
  std::ifstream in(file, std::ios::binary | std::ios::ate);
  if (!in) fail(file, "cannot open");
  const std::streamsize size = in.tellg();
  if (size < 0) fail(file, "cannot determine size");
  std::vector<char> data(static_cast<std::size_t>(size));
  in.seekg(0);
  if (size > 0 && !in.read(data.data(), size)) fail(file, "read error");
  return data;
}

template <typename T>
std::vector<T> readArray(const fs::path& file, std::size_t group) {
  const std::vector<char> bytes = readAll(file);
  if (bytes.size() % (sizeof(T) * group) != 0)
    fail(file, "size " + std::to_string(bytes.size()) + " is not a multiple of " +
                   std::to_string(sizeof(T) * group) + " bytes");
  std::vector<T> out(bytes.size() / sizeof(T));
  std::copy(bytes.begin(), bytes.end(), reinterpret_cast<char*>(out.data()));
  return out;
}

template <typename T>
void writeArray(const fs::path& file, const T* data, std::size_t n) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  if (!out) fail(file, "cannot open for writing");
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(n * sizeof(T)));
  if (!out) fail(file, "write error");
}

// Parses n numbers from a line; false if fewer are present or any is not finite.
bool parseNumbers(const std::string& line, double* v, int n) {
  std::istringstream ss(line);
  for (int i = 0; i < n; ++i)
    if (!(ss >> v[i]) || !std::isfinite(v[i])) return false;
  return true;
}

Eigen::Isometry3d fromRowMajor(const double* v) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) m(r, c) = v[4 * r + c];
  Eigen::Isometry3d t;
  t.matrix() = m;
  return t;
}

bool isBlankOrComment(const std::string& line) {
  const auto p = line.find_first_not_of(" \t\r");
  return p == std::string::npos || line[p] == '#';
}

}  // namespace

Points readKittiBin(const fs::path& file, std::vector<float>* reflectance) {
  const std::vector<float> raw = readArray<float>(file, 4);
  Points points(raw.size() / 4);
  if (reflectance) reflectance->resize(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    points[i] = Eigen::Vector3f(raw[4 * i], raw[4 * i + 1], raw[4 * i + 2]);
    if (reflectance) (*reflectance)[i] = raw[4 * i + 3];
  }
  return points;
}

Points readXyzBin(const fs::path& file) {
  const std::vector<float> raw = readArray<float>(file, 3);
  Points points(raw.size() / 3);
  for (std::size_t i = 0; i < points.size(); ++i)
    points[i] = Eigen::Vector3f(raw[3 * i], raw[3 * i + 1], raw[3 * i + 2]);
  return points;
}

std::vector<float> readFloatBin(const fs::path& file) {
  return readArray<float>(file, 1);
}

std::vector<std::uint32_t> readSemanticKittiLabels(const fs::path& file) {
  return readArray<std::uint32_t>(file, 1);
}

Poses readKittiPoses(const fs::path& file) {
  std::ifstream in(file);
  if (!in) fail(file, "cannot open");
  Poses poses;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (isBlankOrComment(line)) continue;
    double v[12];
    if (!parseNumbers(line, v, 12))
      fail(file, "line " + std::to_string(n) + ": expected 12 finite numbers");
    poses.push_back(fromRowMajor(v));
  }
  return poses;
}

Poses readTumPoses(const fs::path& file, std::vector<double>* stamps) {
  std::ifstream in(file);
  if (!in) fail(file, "cannot open");
  Poses poses;
  if (stamps) stamps->clear();
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (isBlankOrComment(line)) continue;
    double v[8];
    if (!parseNumbers(line, v, 8))
      fail(file, "line " + std::to_string(n) + ": expected 8 finite numbers (t x y z qx qy qz qw)");
    const Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
    if (std::abs(q.norm() - 1.0) > 1e-3)
      fail(file, "line " + std::to_string(n) + ": quaternion is not unit length");
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.linear() = q.normalized().toRotationMatrix();
    t.translation() = Eigen::Vector3d(v[1], v[2], v[3]);
    poses.push_back(t);
    if (stamps) stamps->push_back(v[0]);
  }
  return poses;
}

Eigen::Isometry3d readKittiCalibTr(const fs::path& file) {
  std::ifstream in(file);
  if (!in) fail(file, "cannot open");
  std::string line;
  std::vector<std::string> bare;
  while (std::getline(in, line)) {
    if (line.rfind("Tr:", 0) == 0) {
      double v[12];
      if (!parseNumbers(line.substr(3), v, 12)) fail(file, "Tr: expects 12 finite numbers");
      return fromRowMajor(v);
    }
    if (!isBlankOrComment(line)) bare.push_back(line);
  }
  double v[12];
  if (bare.size() == 1 && parseNumbers(bare.front(), v, 12)) return fromRowMajor(v);
  fail(file, "no 'Tr:' line");
}

std::vector<double> readTimes(const fs::path& file) {
  std::ifstream in(file);
  if (!in) fail(file, "cannot open");
  std::vector<double> times;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (isBlankOrComment(line)) continue;
    double t;
    if (!parseNumbers(line, &t, 1)) fail(file, "line " + std::to_string(n) + ": not a number");
    times.push_back(t);
  }
  return times;
}

void writeKittiBin(const fs::path& file, const Points& points, const std::vector<float>* refl) {
  std::vector<float> raw(points.size() * 4);
  for (std::size_t i = 0; i < points.size(); ++i) {
    raw[4 * i] = points[i].x();
    raw[4 * i + 1] = points[i].y();
    raw[4 * i + 2] = points[i].z();
    raw[4 * i + 3] = (refl && i < refl->size()) ? (*refl)[i] : 0.f;
  }
  writeArray(file, raw.data(), raw.size());
}

void writeSemanticKittiLabels(const fs::path& file, const std::vector<std::uint32_t>& labels) {
  writeArray(file, labels.data(), labels.size());
}

void writeKittiPoses(const fs::path& file, const Poses& poses) {
  std::ofstream out(file);
  if (!out) fail(file, "cannot open for writing");
  out << std::setprecision(9) << std::scientific;
  for (const auto& p : poses) {
    const Eigen::Matrix4d& m = p.matrix();
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) out << m(r, c) << ((r == 2 && c == 3) ? '\n' : ' ');
  }
  if (!out) fail(file, "write error");
}

void writeTumPoses(const fs::path& file, const Poses& poses, const std::vector<double>& stamps) {
  std::ofstream out(file);
  if (!out) fail(file, "cannot open for writing");
  out << std::setprecision(9) << std::fixed;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const Eigen::Quaterniond q(poses[i].linear());
    const Eigen::Vector3d& t = poses[i].translation();
    out << (i < stamps.size() ? stamps[i] : static_cast<double>(i)) << ' ' << t.x() << ' ' << t.y()
        << ' ' << t.z() << ' ' << q.x() << ' ' << q.y() << ' ' << q.z() << ' ' << q.w() << '\n';
  }
  if (!out) fail(file, "write error");
}

KittiSequence listKittiSequence(const fs::path& root) {
  KittiSequence seq;
  seq.root = root;
  const fs::path velo = root / "velodyne";
  if (!fs::is_directory(velo)) fail(root, "no velodyne/ directory");
  for (const auto& e : fs::directory_iterator(velo))
    if (e.is_regular_file() && e.path().extension() == ".bin") seq.scans.push_back(e.path());
  std::sort(seq.scans.begin(), seq.scans.end());
  if (seq.scans.empty()) fail(velo, "no .bin scans");
  for (const auto& s : seq.scans) {
    const fs::path label = root / "labels" / s.filename().replace_extension(".label");
    seq.labels.push_back(fs::exists(label) ? label : fs::path());
  }
  return seq;
}

Poses cameraToLidarPoses(const Poses& camera_poses, const Eigen::Isometry3d& tr) {
  Poses out;
  out.reserve(camera_poses.size());
  const Eigen::Isometry3d tr_inv = tr.inverse();
  for (const auto& p : camera_poses) out.push_back(tr_inv * p * tr);
  return out;
}

Poses readKittiLidarPoses(const fs::path& root) {
  return cameraToLidarPoses(readKittiPoses(root / "poses.txt"),
                            readKittiCalibTr(root / "calib.txt"));
}

Poses readKittiGtLidarPoses(const fs::path& gt_dir, int sequence) {
  if (sequence < 0 || sequence > 10 || sequence == 3)
    throw std::runtime_error("KITTI sequence " + std::to_string(sequence) +
                             ": no LiDAR calibration in " + gt_dir.string() +
                             " (00-02 and 04-10 only)");
  char name[16];
  std::snprintf(name, sizeof(name), "%02d.txt", sequence);
  const fs::path calib = gt_dir / (sequence <= 2 ? "calib_00-02.txt" : "calib_04-10_Tr.txt");
  return cameraToLidarPoses(readKittiPoses(gt_dir / "poses" / name), readKittiCalibTr(calib));
}

}  // namespace socc
