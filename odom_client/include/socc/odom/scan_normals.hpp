#pragma once
// Surface normals of a (downsampled) scan from its own points. A map voxel of fewer than 5
// points has no known geometry; pairing a scan point with its first point aligns the sensor's
// sampling pattern (its rings) with the one that made the map, which on a young map of a sparse
// sensor means "standing still". Where the scan itself shows a surface, the pair is taken along
// that surface's normal instead (registration.hpp).
#include <cstdint>
#include <memory>
#include <vector>

#include "socc/point_cloud.hpp"

namespace socc::odom {

/// The normals of a scan's points, each worked out the first time it is asked for: registration
/// needs them only for points paired with voxels of unknown geometry (few of a dense sensor's
/// pairs, most of a young sparse map's), and a neighbour search per point is most of a frame's
/// registration time otherwise.
class ScanNormals {
 public:
  /// on_ground (optional, one flag per point): the point's label is a ground class. A ring
  /// across the ground is a curve in the ground's plane, so there one ring's neighbours do give
  /// the surface's normal: far from a sparse sensor the only neighbours a ground point has, and
  /// unlike two rings not tilted by the lasers' different elevation errors (docs/robustness.md
  /// "One ring across the ground").
  ScanNormals(Points points, double radius, double planarity_threshold,
              std::vector<std::uint8_t> on_ground = {});
  ~ScanNormals();
  ScanNormals(ScanNormals&&) noexcept;
  ScanNormals& operator=(ScanNormals&&) noexcept;

  std::size_t size() const { return normals_.size(); }
  /// Point i's unit normal: of the plane through its nearest neighbours within radius (at least
  /// 5, planarity below planarity_threshold, spread over a surface rather than along one ring's
  /// line, and over more than one ring unless it is on the ground: the points are in the
  /// sensor's frame, and one ring's points share an elevation seen from it); zero where the
  /// neighbourhood is no such plane.
  /// Calls for distinct i may run at once.
  const Eigen::Vector3f& at(std::size_t i) const;

 private:
  struct Search;
  std::unique_ptr<const Search> search_;
  // Filled in by at(): one element per point, each written by the one call that asks for it.
  mutable std::vector<Eigen::Vector3f> normals_;
  mutable std::vector<std::uint8_t> known_;
};

}  // namespace socc::odom
