#include "socc/trajectory_revision.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "socc/pose_interpolation.hpp"

namespace socc {
namespace {

// The corrections applied to the output pose at seq, composed in their order (sorted by seq).
Eigen::Isometry3d outputFrame(const std::vector<FrameCorrection>& sorted, std::int64_t seq) {
  Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();
  for (const FrameCorrection& c : sorted) {
    if (c.from_seq > seq) break;
    frame = c.correction * frame;
  }
  return frame;
}

void checkInput(const std::vector<std::int64_t>& seqs, const Poses& poses) {
  if (seqs.size() != poses.size())
    throw std::invalid_argument("reviseTrajectory: " + std::to_string(seqs.size()) + " seqs but " +
                                std::to_string(poses.size()) + " poses");
  for (std::size_t i = 1; i < seqs.size(); ++i)
    if (seqs[i] <= seqs[i - 1])
      throw std::invalid_argument("reviseTrajectory: seqs do not increase at index " +
                                  std::to_string(i));
}

struct Anchor {
  std::size_t index = 0;  // of the output pose
  Eigen::Isometry3d revision = Eigen::Isometry3d::Identity();
};

}  // namespace

RevisedTrajectory reviseTrajectory(const std::vector<std::int64_t>& seqs, const Poses& poses,
                                   const std::vector<KeyframeEstimate>& keyframes,
                                   const std::vector<FrameCorrection>& corrections) {
  checkInput(seqs, poses);
  std::vector<FrameCorrection> sorted = corrections;
  std::stable_sort(sorted.begin(), sorted.end(),
                   [](const auto& a, const auto& b) { return a.from_seq < b.from_seq; });
  Poses first_frame(poses.size());  // every output pose in the robot's first frame
  for (std::size_t i = 0; i < poses.size(); ++i)
    first_frame[i] = outputFrame(sorted, seqs[i]).inverse() * poses[i];

  std::vector<Anchor> anchors;
  for (const KeyframeEstimate& k : keyframes) {
    const auto it = std::lower_bound(seqs.begin(), seqs.end(), k.seq);
    if (it == seqs.end() || *it != k.seq) continue;
    const auto i = static_cast<std::size_t>(it - seqs.begin());
    anchors.push_back({i, k.pose * first_frame[i].inverse()});
  }
  std::sort(anchors.begin(), anchors.end(),
            [](const Anchor& a, const Anchor& b) { return a.index < b.index; });

  RevisedTrajectory out;
  out.keyframes = static_cast<int>(anchors.size());
  if (anchors.empty()) {
    out.poses = poses;
    return out;
  }
  out.poses.reserve(poses.size());
  std::size_t next = 0;  // the first anchor at or after i
  for (std::size_t i = 0; i < poses.size(); ++i) {
    while (next < anchors.size() && anchors[next].index < i) ++next;
    Eigen::Isometry3d revision;
    if (next == 0)
      revision = anchors.front().revision;
    else if (next == anchors.size())
      revision = anchors.back().revision;
    else {
      const Anchor& a = anchors[next - 1];
      const Anchor& b = anchors[next];
      const double s = static_cast<double>(seqs[i] - seqs[a.index]) /
                       static_cast<double>(seqs[b.index] - seqs[a.index]);
      revision = interpolatePose(a.revision, b.revision, s);
    }
    out.poses.push_back(revision * first_frame[i]);
    out.max_shift =
        std::max(out.max_shift, (out.poses.back().translation() - poses[i].translation()).norm());
  }
  return out;
}

}  // namespace socc
