#include "robot_corrections.hpp"

#include <cmath>
#include <iomanip>
#include <sstream>

namespace socc::service {
namespace {

void writeTransform(std::ostream& out, const Eigen::Isometry3d& t) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) out << ' ' << t.matrix()(r, c);
}

bool readTransform(std::istream& in, Eigen::Isometry3d& t) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c)
      if (!(in >> m(r, c)) || !std::isfinite(m(r, c))) return false;
  const Eigen::Matrix3d rotation = m.topLeftCorner<3, 3>();
  if (!(rotation * rotation.transpose()).isIdentity(1e-6)) return false;
  t = Eigen::Isometry3d(m);
  return true;
}

}  // namespace

RobotCorrections::Incoming RobotCorrections::incoming(const std::string& robot, std::int64_t seq,
                                                      const Eigen::Isometry3d& pose) {
  Incoming out;
  const auto it = robots_.find(robot);
  if (it == robots_.end()) {  // never corrected: all its poses are raw and in the grid's frame
    out.raw = pose;
    out.map = pose;
    return out;
  }
  Robot& r = it->second;
  out.raw = r.frame.inverse() * pose;
  out.map = pose;
  if (r.offered) {
    // Registered against the old grid: moved into the new one, and the robot is told.
    out.map = *r.offered * out.raw;
    r.told = *r.offered * r.frame.inverse();
    r.told_seq = seq;
    r.frame = *r.offered;
    r.offered.reset();
    out.told = r.told;
  }
  return out;
}

std::optional<Eigen::Isometry3d> RobotCorrections::toldWith(const std::string& robot,
                                                            std::int64_t seq) const {
  const auto it = robots_.find(robot);
  if (it == robots_.end() || it->second.told_seq != seq) return std::nullopt;
  return it->second.told;
}

Eigen::Isometry3d RobotCorrections::frame(const std::string& robot) const {
  const auto it = robots_.find(robot);
  return it == robots_.end() ? Eigen::Isometry3d::Identity() : it->second.frame;
}

void RobotCorrections::offer(const std::string& robot, const Eigen::Isometry3d& raw_to_map) {
  robots_[robot].offered = raw_to_map;
}

std::string RobotCorrections::serialize() const {
  std::ostringstream out;
  out.precision(17);
  for (const auto& [name, r] : robots_) {
    out << std::quoted(name) << ' ' << r.told_seq << ' ' << (r.offered ? 1 : 0);
    writeTransform(out, r.frame);
    writeTransform(out, r.offered.value_or(Eigen::Isometry3d::Identity()));
    writeTransform(out, r.told);
    out << '\n';
  }
  return out.str();
}

bool RobotCorrections::parse(const std::string& text) {
  std::map<std::string, Robot> robots;
  std::istringstream in(text);
  std::string name;
  while (in >> std::quoted(name)) {
    Robot r;
    int offered = 0;
    Eigen::Isometry3d offer = Eigen::Isometry3d::Identity();
    if (!(in >> r.told_seq >> offered) || !readTransform(in, r.frame) ||
        !readTransform(in, offer) || !readTransform(in, r.told))
      return false;
    if (offered == 1) r.offered = offer;
    robots[name] = r;
  }
  if (!in.eof()) return false;
  robots_ = std::move(robots);
  return true;
}

int RobotCorrections::waiting() const {
  int n = 0;
  for (const auto& [name, r] : robots_) n += r.offered ? 1 : 0;
  return n;
}

}  // namespace socc::service
