#include "socc/chunk_features.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "socc/rounding.hpp"
namespace socc::chunk {
namespace {

constexpr double kOffsetSteps = 65535.0;
constexpr double kPlanarityScale = 762.0;  // 3 * 254: tau <= 1/3 fills 0..254

double signNotZero(double v) {
  return v >= 0.0 ? 1.0 : -1.0;
}

std::int16_t unitToInt16(double v) {
  return static_cast<std::int16_t>(roundHalfAway(std::clamp(v, -1.0, 1.0) * 32767.0));
}

}  // namespace

std::int16_t encodeOffset(double offset, double block_size) {
  const double steps = std::clamp(offset / block_size, 0.0, 1.0) * kOffsetSteps;
  return static_cast<std::int16_t>(roundHalfAway(steps) - 32768);
}

double decodeOffset(std::int16_t q, double block_size) {
  return (static_cast<double>(q) + 32768.0) / kOffsetSteps * block_size;
}

std::array<std::int16_t, 2> encodeNormal(const Eigen::Vector3d& normal) {
  const double l1 = normal.cwiseAbs().sum();
  if (!(l1 > 0.0)) return {0, 0};
  Eigen::Vector3d n = normal / l1;
  double u = n.x(), v = n.y();
  if (n.z() < 0.0) {  // the lower half folded over the diagonals
    u = (1.0 - std::abs(n.y())) * signNotZero(n.x());
    v = (1.0 - std::abs(n.x())) * signNotZero(n.y());
  }
  return {unitToInt16(u), unitToInt16(v)};
}

Eigen::Vector3d decodeNormal(std::int16_t a, std::int16_t b) {
  const double u = a / 32767.0, v = b / 32767.0;
  Eigen::Vector3d n(u, v, 1.0 - std::abs(u) - std::abs(v));
  if (n.z() < 0.0) {
    n.x() = (1.0 - std::abs(v)) * signNotZero(u);
    n.y() = (1.0 - std::abs(u)) * signNotZero(v);
  }
  return n.normalized();
}

std::int16_t encodeScatter(double value, std::uint32_t count, double voxel_size) {
  const double range = count * voxel_size * voxel_size;
  if (!(range > 0.0)) return 0;
  return static_cast<std::int16_t>(roundHalfAway(std::clamp(value / range, -1.0, 1.0) * 32767.0));
}

double decodeScatter(std::int16_t q, std::uint32_t count, double voxel_size) {
  return q / 32767.0 * count * voxel_size * voxel_size;
}

std::int16_t encodeMeanOffset(double offset, double voxel_size) {
  const double steps = offset * (32767.0 / voxel_size);
  return static_cast<std::int16_t>(roundHalfAway(std::clamp(steps, -32767.0, 32767.0)));
}

double decodeMeanOffset(std::int16_t q, double voxel_size) {
  return q * (voxel_size / 32767.0);
}

std::uint8_t encodePlanarity(double tau) {
  if (!(tau >= 0.0)) return kUnknownPlanarity;
  return static_cast<std::uint8_t>(roundHalfAway(std::min(tau * kPlanarityScale, 254.0)));
}

double decodePlanarity(std::uint8_t q) {
  return q == kUnknownPlanarity ? -1.0 : q / kPlanarityScale;
}

Eigen::Vector3d blockCorner(const Eigen::Vector3i& key, int block_dim, double voxel_size) {
  return key.cast<double>() * (block_dim * voxel_size);
}

std::string checkBlocks(const chunk_reply_t& reply) {
  if (reply.block_dim <= 0) return "block_dim " + std::to_string(reply.block_dim);
  std::int64_t sum = 0;
  for (const std::int32_t n : reply.block_voxels) {
    if (n < 0) return "negative block_voxels";
    sum += n;
  }
  if (sum != reply.num_voxels)
    return "block_voxels add up to " + std::to_string(sum) + ", not num_voxels " +
           std::to_string(reply.num_voxels);
  return {};
}

std::vector<Eigen::Vector3d> firstPoints(const chunk_reply_t& reply) {
  std::vector<Eigen::Vector3d> points;
  if (!checkBlocks(reply).empty() || reply.n_features != reply.num_voxels ||
      reply.first_point.size() != 3)
    return points;
  const double block_size = reply.block_dim * reply.voxel_size;
  points.reserve(static_cast<std::size_t>(reply.num_voxels));
  for (std::size_t b = 0; b < reply.block_voxels.size(); ++b) {
    const Eigen::Vector3d corner =
        blockCorner({reply.block[0][b], reply.block[1][b], reply.block[2][b]}, reply.block_dim,
                    reply.voxel_size);
    for (std::int32_t k = 0; k < reply.block_voxels[b]; ++k) {
      const std::size_t i = points.size();
      points.push_back(corner + Eigen::Vector3d(decodeOffset(reply.first_point[0][i], block_size),
                                                decodeOffset(reply.first_point[1][i], block_size),
                                                decodeOffset(reply.first_point[2][i], block_size)));
    }
  }
  return points;
}

}  // namespace socc::chunk
