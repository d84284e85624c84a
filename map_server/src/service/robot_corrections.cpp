#include "robot_corrections.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <set>
#include <sstream>

namespace socc::service {
namespace {

// Map instances remembered: every restart, load, clear and correction makes one. A request of
// an instance forgotten is taken in the frame its robot was last told.
constexpr std::size_t kMaxEpochs = 64;

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

void RobotCorrections::serving(std::int64_t epoch) {
  epochs_.emplace(epoch, generation_);
  if (epochs_.size() <= kMaxEpochs) return;
  epochs_.erase(std::min_element(epochs_.begin(), epochs_.end(),
                                 [](const auto& a, const auto& b) { return a.second < b.second; }));
}

void RobotCorrections::corrected(std::int64_t epoch,
                                 const std::map<std::string, Eigen::Isometry3d>& raw_to_map) {
  ++generation_;
  for (const auto& [robot, correction] : raw_to_map)
    robots_[robot].frames[generation_] = correction;
  serving(epoch);
  for (auto& [name, robot] : robots_) keepNeededFrames(robot);
}

Eigen::Isometry3d RobotCorrections::frameAt(const Robot& robot, int generation) {
  auto it = robot.frames.upper_bound(generation);
  return it == robot.frames.begin() ? Eigen::Isometry3d::Identity() : (--it)->second;
}

int RobotCorrections::generationOf(const Robot& robot, std::int64_t epoch) const {
  const auto it = epoch == 0 ? epochs_.end() : epochs_.find(epoch);
  return it == epochs_.end() ? robot.generation : it->second;
}

void RobotCorrections::keepNeededFrames(Robot& robot) const {
  // A request is in the generation of a remembered instance, or (unknown instance) in the
  // robot's own; the reply compares it with the current one. Only the entries in force at those
  // generations are ever read: at most kMaxEpochs + 2, however long a robot stays away.
  std::set<int> needed{robot.generation, generation_};
  for (const auto& [epoch, generation] : epochs_) needed.insert(generation);
  std::map<int, Eigen::Isometry3d> kept;
  for (const int generation : needed) {
    auto in_force = robot.frames.upper_bound(generation);
    if (in_force != robot.frames.begin()) kept.insert(*--in_force);
  }
  robot.frames = std::move(kept);
}

RobotCorrections::Incoming RobotCorrections::incoming(const std::string& robot, std::int64_t seq,
                                                      const Eigen::Isometry3d& pose,
                                                      std::int64_t pose_epoch) {
  Incoming out;
  const auto it = robots_.find(robot);
  if (it == robots_.end()) {  // never corrected: all its poses are raw and in the grid's frame
    out.raw = pose;
    out.map = pose;
    return out;
  }
  Robot& r = it->second;
  const int sent_in = generationOf(r, pose_epoch);
  const Eigen::Isometry3d sent_frame = frameAt(r, sent_in);
  const Eigen::Isometry3d now = frameAt(r, generation_);
  out.raw = sent_frame.inverse() * pose;
  out.map = now * out.raw;
  if (r.frames.upper_bound(sent_in) != r.frames.end()) {
    // Registered against an older grid than this robot's last correction: moved into the
    // current one, and the robot is told.
    r.told = now * sent_frame.inverse();
    r.told_seq = seq;
    out.told = r.told;
  }
  r.generation = generation_;
  keepNeededFrames(r);
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
  return it == robots_.end() ? Eigen::Isometry3d::Identity() : frameAt(it->second, generation_);
}

int RobotCorrections::waiting() const {
  int n = 0;
  for (const auto& [name, r] : robots_)
    n += r.frames.upper_bound(r.generation) != r.frames.end() ? 1 : 0;
  return n;
}

std::string RobotCorrections::serialize() const {
  if (generation_ == 0) return {};  // nothing corrected: instances all share the first frame
  std::ostringstream out;
  out.precision(17);
  out << "generation " << generation_ << '\n';
  for (const auto& [epoch, generation] : epochs_)
    out << "epoch " << epoch << ' ' << generation << '\n';
  for (const auto& [name, r] : robots_) {
    out << "robot " << std::quoted(name) << ' ' << r.generation << ' ' << r.told_seq;
    writeTransform(out, r.told);
    out << ' ' << r.frames.size();
    for (const auto& [generation, frame] : r.frames) {
      out << ' ' << generation;
      writeTransform(out, frame);
    }
    out << '\n';
  }
  return out.str();
}

bool RobotCorrections::parse(const std::string& text) {
  std::istringstream in(text);
  std::string word;
  if (!(in >> word)) {
    clear();
    return true;
  }
  if (word != "generation") return parseLegacy(text);
  RobotCorrections parsed;
  if (!(in >> parsed.generation_) || parsed.generation_ < 0) return false;
  while (in >> word) {
    if (word == "epoch") {
      std::int64_t epoch = 0;
      int generation = 0;
      if (!(in >> epoch >> generation) || generation < 0 || generation > parsed.generation_)
        return false;
      parsed.epochs_[epoch] = generation;
      continue;
    }
    std::string name;
    Robot r;
    std::size_t frames = 0;
    if (word != "robot" || !(in >> std::quoted(name) >> r.generation >> r.told_seq) ||
        !readTransform(in, r.told) || !(in >> frames) || frames > kMaxEpochs + 2)
      return false;
    for (std::size_t i = 0; i < frames; ++i) {
      int generation = 0;
      Eigen::Isometry3d frame;
      if (!(in >> generation) || !readTransform(in, frame)) return false;
      r.frames[generation] = frame;
    }
    parsed.robots_[name] = r;
  }
  if (!in.eof()) return false;
  *this = std::move(parsed);
  return true;
}

bool RobotCorrections::parseLegacy(const std::string& text) {
  // Before map instances were named: per robot its told seq, whether a correction waited, the
  // frame it was last told, the waiting correction and the last one told. Restored as a first
  // generation (the frames told) and, when any robot waited, a second one (theirs).
  RobotCorrections parsed;
  parsed.generation_ = 1;
  std::istringstream in(text);
  std::string name;
  while (in >> std::quoted(name)) {
    Robot r;
    int offered = 0;
    Eigen::Isometry3d frame;
    Eigen::Isometry3d offer;
    if (!(in >> r.told_seq >> offered) || !readTransform(in, frame) || !readTransform(in, offer) ||
        !readTransform(in, r.told))
      return false;
    r.generation = 1;
    r.frames[1] = frame;
    if (offered == 1) {
      r.frames[2] = offer;
      parsed.generation_ = 2;
    }
    parsed.robots_[name] = r;
  }
  if (!in.eof()) return false;
  *this = std::move(parsed);
  return true;
}

}  // namespace socc::service
