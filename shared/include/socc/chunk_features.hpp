#pragma once
// The compact per-voxel encoding of a chunk reply's FIELD_FEATURES (docs/lcm.md "Chunk
// encoding"), the one implementation for the map server (encode) and its clients (decode):
// - first point: int16 offsets from its block's corner, in steps of block size / 65535 (0.06 mm
//   for the default 4 m blocks);
// - normal: a unit vector, octahedral, two int16 (error < 0.01 deg);
// - planarity tau in [0, 1/3]: a byte, tau * 762 rounded (error < 0.0007); 255 when unknown, and
//   then the normal is unknown too (fewer than 5 points);
// - FIELD_MOMENTS: point counts in a byte, means as int16 offsets from the first point, sums of
//   squared deviations as int16 of their range (encodeScatter).
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "socc/chunk_reply_t.hpp"

namespace socc::chunk {

inline constexpr std::uint8_t kUnknownPlanarity = 255;

/// FIELD_MOMENTS: voxels of fewer points than this come with their moments, i.e. all whose count
/// fits the point_count byte: the few points a scan adds still move the normal and planarity of a
/// sparse sensor's voxels of a hundred points (and give a voxel of fewer than 5 its first).
inline constexpr std::uint32_t kMomentsBelow = 255;

/// A component of a voxel's sum of squared deviations (|value| <= count * voxel_size^2 inside
/// the voxel) as an int16 of that range: steps of count * voxel_size^2 / 32767, which resolve a
/// plane's thickness 6x finer than the planarity byte.
std::int16_t encodeScatter(double value, std::uint32_t count, double voxel_size);
double decodeScatter(std::int16_t q, std::uint32_t count, double voxel_size);

/// A component of a voxel's mean as an offset [m] from its first point (within one voxel_size,
/// clamped), an int16 of steps voxel_size / 32767.
std::int16_t encodeMeanOffset(double offset, double voxel_size);
double decodeMeanOffset(std::int16_t q, double voxel_size);

/// Offset [m] of a coordinate from its block's corner, in [0, block_size] (clamped).
std::int16_t encodeOffset(double offset, double block_size);
double decodeOffset(std::int16_t q, double block_size);

/// A unit normal (any non-zero vector is normalised; zero gives +z).
std::array<std::int16_t, 2> encodeNormal(const Eigen::Vector3d& normal);
Eigen::Vector3d decodeNormal(std::int16_t a, std::int16_t b);

/// Negative (unknown) gives kUnknownPlanarity.
std::uint8_t encodePlanarity(double tau);
/// -1 for kUnknownPlanarity.
double decodePlanarity(std::uint8_t q);

/// The map-frame corner of block key.
Eigen::Vector3d blockCorner(const Eigen::Vector3i& key, int block_dim, double voxel_size);

/// The first points of a reply's voxels, from their block offsets. Empty when the block lists do
/// not add up to the voxels (check with checkBlocks first).
std::vector<Eigen::Vector3d> firstPoints(const chunk_reply_t& reply);

/// Empty when the block lists are consistent (block_dim > 0, counts >= 0 that add up to
/// num_voxels); otherwise the problem.
std::string checkBlocks(const chunk_reply_t& reply);

}  // namespace socc::chunk
