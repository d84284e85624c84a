#include "store_records.hpp"

#include <optional>
#include <stdexcept>

#include "byte_io.hpp"

namespace socc::consistency {
namespace {

using map::ByteReader;
using map::ByteWriter;

void putPose(ByteWriter& w, const Eigen::Isometry3d& pose) {
  const Eigen::Matrix<double, 3, 4> m = pose.matrix().topRows<3>();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) w.put<double>(m(r, c));
}

Eigen::Isometry3d getPose(ByteReader& r) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  for (int i = 0; i < 3; ++i)
    for (int c = 0; c < 4; ++c) m(i, c) = r.get<double>();
  return Eigen::Isometry3d(m);
}

void putInformation(ByteWriter& w, const Matrix6d& information) {
  for (int i = 0; i < 36; ++i) w.put<double>(information.data()[i]);
}

Matrix6d getInformation(ByteReader& r) {
  Matrix6d m;
  for (int i = 0; i < 36; ++i) m.data()[i] = r.get<double>();
  return m;
}

void putEdge(ByteWriter& w, const PoseEdge& e) {
  w.put<std::int32_t>(e.from);
  w.put<std::int32_t>(e.to);
  putPose(w, e.relative);
  putInformation(w, e.information);
}

PoseEdge getEdge(ByteReader& r) {
  PoseEdge e;
  e.from = r.get<std::int32_t>();
  e.to = r.get<std::int32_t>();
  e.relative = getPose(r);
  e.information = getInformation(r);
  return e;
}

// A count of elements of at least min_bytes each: never more than the payload can hold.
std::size_t getCount(ByteReader& r, std::size_t min_bytes) {
  const auto n = r.get<std::uint64_t>();
  if (n > r.remaining() / min_bytes) throw std::runtime_error("record count exceeds its size");
  return static_cast<std::size_t>(n);
}

template <typename T>
void putArray(ByteWriter& w, const std::vector<T>& values) {
  w.put<std::uint64_t>(values.size());
  for (const T& v : values) w.put<T>(v);
}

template <typename T>
std::vector<T> getArray(ByteReader& r) {
  std::vector<T> out(getCount(r, sizeof(T)));
  for (T& v : out) v = r.get<T>();
  return out;
}

void putScan(ByteWriter& w, const KeyframeScan& scan) {
  w.put<float>(scan.resolution);
  w.put<std::uint64_t>(scan.xyz.size());
  for (const auto& axis : scan.xyz) putArray(w, axis);
  putArray(w, scan.labels);
}

KeyframeScan getScan(ByteReader& r) {
  KeyframeScan scan;
  scan.resolution = r.get<float>();
  scan.xyz.resize(getCount(r, sizeof(std::uint64_t)));
  for (auto& axis : scan.xyz) axis = getArray<std::int16_t>(r);
  scan.labels = getArray<std::uint8_t>(r);
  for (const auto& axis : scan.xyz)
    if (axis.size() != scan.labels.size()) throw std::runtime_error("scan sizes differ");
  return scan;
}

void putKeyframeFields(ByteWriter& w, const Keyframe& k) {
  w.put<std::int32_t>(k.id);
  w.put<std::int32_t>(k.robot);
  w.put<std::int32_t>(k.robot_kf);
  w.put<std::int64_t>(k.seq);
  w.put<std::int64_t>(k.utime);
  putPose(w, k.odom_pose);
  w.put<double>(k.travelled);
  putPose(w, k.grid_pose);
  w.put<std::uint64_t>(k.points.size());
  for (const Eigen::Vector3f& p : k.points)
    for (int i = 0; i < 3; ++i) w.put<float>(p[i]);
  putScan(w, k.scan);
}

Keyframe getKeyframeFields(ByteReader& r) {
  Keyframe k;
  k.id = r.get<std::int32_t>();
  k.robot = r.get<std::int32_t>();
  k.robot_kf = r.get<std::int32_t>();
  k.seq = r.get<std::int64_t>();
  k.utime = r.get<std::int64_t>();
  k.odom_pose = getPose(r);
  k.travelled = r.get<double>();
  k.grid_pose = getPose(r);
  k.points.resize(getCount(r, 3 * sizeof(float)));
  for (Eigen::Vector3f& p : k.points)
    for (int i = 0; i < 3; ++i) p[i] = r.get<float>();
  k.scan = getScan(r);
  return k;
}

// A keyframe's gravity reference, after every other field of its record (keyframe and waiting):
// written only when it has one, so a store without references is byte for byte what it was and
// an older map_server reads it; a record from before references ends without it. {uint8 1, up
// (3 doubles), sigma (double)}.
constexpr std::uint8_t kGravityTag = 1;

void putGravity(ByteWriter& w, const std::optional<GravityReference>& gravity) {
  if (!gravity) return;
  w.put<std::uint8_t>(kGravityTag);
  for (int i = 0; i < 3; ++i) w.put<double>(gravity->up[i]);
  w.put<double>(gravity->sigma);
}

std::optional<GravityReference> getGravity(ByteReader& r) {
  if (r.remaining() == 0) return std::nullopt;
  if (r.get<std::uint8_t>() != kGravityTag)
    throw std::runtime_error("keyframe: unknown field after its record");
  Eigen::Vector3d up;
  for (int i = 0; i < 3; ++i) up[i] = r.get<double>();
  const double sigma = r.get<double>();
  std::optional<GravityReference> gravity = gravityReference(up, sigma);
  if (!gravity) throw std::runtime_error("keyframe: a gravity reference without a direction");
  return gravity;
}

void expectEnd(const ByteReader& r) {
  if (r.remaining() != 0) throw std::runtime_error("record longer than its fields");
}

}  // namespace

std::string encodeKeyframe(const StoredKeyframe& record) {
  ByteWriter w;
  w.putBytes(record.robot);
  putKeyframeFields(w, record.keyframe);
  putPose(w, record.estimate);
  w.put<std::uint64_t>(record.edges.size());
  for (const PoseEdge& e : record.edges) putEdge(w, e);
  w.put<std::uint64_t>(record.priors.size());
  for (const PosePrior& p : record.priors) {
    w.put<std::int32_t>(p.node);
    putPose(w, p.pose);
    putInformation(w, p.information);
    w.put<std::uint8_t>(p.fixed ? 1 : 0);
  }
  putGravity(w, record.keyframe.gravity);
  return w.bytes();
}

StoredKeyframe decodeKeyframe(const std::string& payload) {
  ByteReader r(payload.data(), payload.size());
  StoredKeyframe out;
  out.robot = r.getBytes();
  out.keyframe = getKeyframeFields(r);
  out.estimate = getPose(r);
  out.edges.resize(getCount(r, 8));
  for (PoseEdge& e : out.edges) e = getEdge(r);
  out.priors.resize(getCount(r, 8));
  for (PosePrior& p : out.priors) {
    p.node = r.get<std::int32_t>();
    p.pose = getPose(r);
    p.information = getInformation(r);
    p.fixed = r.get<std::uint8_t>() != 0;
  }
  out.keyframe.gravity = getGravity(r);
  expectEnd(r);
  return out;
}

std::string encodeClosure(const StoredClosure& record) {
  ByteWriter w;
  const Closure& c = record.closure;
  w.put<std::int32_t>(c.from);
  w.put<std::int32_t>(c.to);
  putPose(w, c.relative);
  w.put<double>(c.fitness);
  w.put<double>(c.free);
  w.put<std::uint8_t>(c.by_descriptor ? 1 : 0);
  putEdge(w, record.edge);
  return w.bytes();
}

StoredClosure decodeClosure(const std::string& payload) {
  ByteReader r(payload.data(), payload.size());
  StoredClosure out;
  Closure& c = out.closure;
  c.from = r.get<std::int32_t>();
  c.to = r.get<std::int32_t>();
  c.relative = getPose(r);
  c.fitness = r.get<double>();
  c.free = r.get<double>();
  c.by_descriptor = r.get<std::uint8_t>() != 0;
  out.edge = getEdge(r);
  expectEnd(r);
  return out;
}

std::string encodeRebuild(const StoredRebuild& record) {
  ByteWriter w;
  w.put<std::int32_t>(record.serial);
  w.put<std::uint64_t>(record.poses.size());
  for (const Eigen::Isometry3d& p : record.poses) putPose(w, p);
  w.put<std::uint64_t>(record.corrections.size());
  for (const auto& [robot, correction] : record.corrections) {
    w.putBytes(robot);
    putPose(w, correction);
  }
  return w.bytes();
}

StoredRebuild decodeRebuild(const std::string& payload) {
  ByteReader r(payload.data(), payload.size());
  StoredRebuild out;
  out.serial = r.get<std::int32_t>();
  out.poses.resize(getCount(r, 12 * sizeof(double)));
  for (Eigen::Isometry3d& p : out.poses) p = getPose(r);
  const std::size_t robots = getCount(r, 8);
  for (std::size_t i = 0; i < robots; ++i) {
    std::string robot = r.getBytes();
    out.corrections[robot] = getPose(r);
  }
  expectEnd(r);
  return out;
}

std::string encodeCheckpoint(const StoredCheckpoint& record) {
  ByteWriter w;
  w.put<std::int64_t>(record.journal_sequence);
  w.put<std::int64_t>(record.map_version);
  w.put<std::int64_t>(record.observed);
  w.put<std::int32_t>(record.grid_serial);
  return w.bytes();
}

StoredCheckpoint decodeCheckpoint(const std::string& payload) {
  ByteReader r(payload.data(), payload.size());
  StoredCheckpoint out;
  out.journal_sequence = r.get<std::int64_t>();
  out.map_version = r.get<std::int64_t>();
  out.observed = r.get<std::int64_t>();
  out.grid_serial = r.get<std::int32_t>();
  expectEnd(r);
  return out;
}

std::string encodeWaiting(const StoredWaiting& record) {
  ByteWriter w;
  w.putBytes(record.robot);
  putKeyframeFields(w, record.keyframe);
  w.put<std::uint8_t>(static_cast<std::uint8_t>(record.form));
  w.put<std::uint64_t>(record.cloud.points.size());
  for (const Eigen::Vector3f& p : record.cloud.points)
    for (int i = 0; i < 3; ++i) w.put<float>(p[i]);
  putArray(w, record.cloud.labels);
  putGravity(w, record.keyframe.gravity);
  return w.bytes();
}

StoredWaiting decodeWaiting(const std::string& payload) {
  ByteReader r(payload.data(), payload.size());
  StoredWaiting out;
  out.robot = r.getBytes();
  out.keyframe = getKeyframeFields(r);
  const auto form = r.get<std::uint8_t>();
  if (form > static_cast<std::uint8_t>(WaitingForm::kReduced))
    throw std::runtime_error("waiting keyframe: unknown form " + std::to_string(form));
  out.form = static_cast<WaitingForm>(form);
  out.cloud.points.resize(getCount(r, 3 * sizeof(float)));
  for (Eigen::Vector3f& p : out.cloud.points)
    for (int i = 0; i < 3; ++i) p[i] = r.get<float>();
  out.cloud.labels = getArray<std::uint8_t>(r);
  if (!out.cloud.consistent())
    throw std::runtime_error("waiting keyframe: labels and points differ");
  if (out.form != WaitingForm::kCloud && !out.cloud.points.empty())
    throw std::runtime_error("waiting keyframe: a cloud in a record without one");
  out.keyframe.gravity = getGravity(r);
  expectEnd(r);
  return out;
}

}  // namespace socc::consistency
