// The static transforms of a bag (socc/sensors/static_transforms.hpp).
#include "socc/sensors/static_transforms.hpp"

#include <map>

#include "bags/bag_reader.hpp"
#include "bags/ros_messages.hpp"

namespace socc::sensors {
namespace {

std::string frameName(const std::string& frame) {
  return !frame.empty() && frame.front() == '/' ? frame.substr(1) : frame;
}

}  // namespace

StaticTransforms StaticTransforms::fromBag(const std::filesystem::path& bag) {
  StaticTransforms out;
  std::unique_ptr<bags::BagReader> reader = bags::openBagReader(bag);
  const std::vector<bags::TopicInfo>& topics = reader->topics();
  for (std::size_t i = 0; i < topics.size(); ++i) {
    if (topics[i].name != "/tf_static" || !bags::isTfMessageType(topics[i].type) ||
        !topics[i].encoding)
      continue;
    reader->select(i);
    while (const std::optional<bags::BagMessage> m = reader->next()) {
      std::vector<bags::TransformMsg> transforms;
      try {
        transforms = bags::parseTfMessage(bags::ByteView(m->data), *topics[i].encoding);
      } catch (const bags::FormatError&) {
        continue;  // one damaged message: the others may still hold the chain
      }
      for (const bags::TransformMsg& t : transforms) {
        Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
        pose.translation() = Eigen::Vector3d(t.translation.data());
        const Eigen::Quaterniond q(t.rotation[3], t.rotation[0], t.rotation[1], t.rotation[2]);
        if (!q.coeffs().allFinite() || !pose.translation().allFinite() || q.norm() < 0.5) continue;
        pose.linear() = q.normalized().toRotationMatrix();
        out.add(t.header.frame_id, t.child_frame_id, pose);
      }
    }
    break;
  }
  return out;
}

void StaticTransforms::add(const std::string& parent, const std::string& child,
                           const Eigen::Isometry3d& parent_T_child) {
  const std::string p = frameName(parent), c = frameName(child);
  for (Edge& e : edges_) {
    if (e.child != c) continue;
    e = {p, c, parent_T_child};  // a frame has one parent: the later transform replaces it
    return;
  }
  edges_.push_back({p, c, parent_T_child});
}

std::optional<Eigen::Isometry3d> StaticTransforms::lookup(const std::string& target,
                                                          const std::string& source) const {
  // target_T_frame of every frame reached from target, grown until nothing changes.
  std::map<std::string, Eigen::Isometry3d> reached = {
      {frameName(target), Eigen::Isometry3d::Identity()}};
  for (bool grew = true; grew;) {
    grew = false;
    for (const Edge& e : edges_) {
      const auto parent = reached.find(e.parent);
      const auto child = reached.find(e.child);
      if (parent != reached.end() && child == reached.end()) {
        reached.emplace(e.child, parent->second * e.parent_T_child);
        grew = true;
      } else if (child != reached.end() && parent == reached.end()) {
        reached.emplace(e.parent, child->second * e.parent_T_child.inverse());
        grew = true;
      }
    }
  }
  const auto found = reached.find(frameName(source));
  if (found == reached.end()) return std::nullopt;
  return found->second;
}

std::string StaticTransforms::describe() const {
  std::string out;
  for (const Edge& e : edges_) out += "  " + e.parent + " -> " + e.child + "\n";
  return out;
}

}  // namespace socc::sensors
