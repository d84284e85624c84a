#pragma once
// Keypoints with FPFH descriptors (PCL): what global localization matches between a scan and
// the map. One recipe for both sides, so that the same surface gives the same descriptor:
// voxel-grid keypoints, normals from their neighbours, normals turned towards the side the
// surface was seen from, FPFH over a wider radius. Keypoints whose normal or descriptor cannot be
// computed (too few neighbours) are dropped.
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <Eigen/Core>
#include <functional>
#include <vector>

namespace socc::localization {

struct FeatureParams {
  double keypoint_voxel = 1.0;  // [m] keypoint spacing
  double normal_radius = 2.0;   // [m]
  double feature_radius = 4.0;  // [m] FPFH support
  // Keypoints on flat surfaces (road, facades) all carry the same descriptor and only add wrong
  // matches: kept are those whose neighbourhood's surface variation (PCL curvature) exceeds this.
  double min_curvature = 0.05;
};

struct FeatureCloud {
  pcl::PointCloud<pcl::PointNormal>::Ptr keypoints{new pcl::PointCloud<pcl::PointNormal>};
  pcl::PointCloud<pcl::FPFHSignature33>::Ptr features{new pcl::PointCloud<pcl::FPFHSignature33>};
  std::size_t size() const { return keypoints->size(); }
};

/// True when the normal n at p points into the surface (away from where it was seen) and must
/// be flipped. Normals start turned towards the origin (the sensor, for a scan).
using NormalSideTest = std::function<bool(const Eigen::Vector3f& p, const Eigen::Vector3f& n)>;

/// Keypoints with normals (turned by flip): the part of describe() that may need the grid.
using OrientedKeypoints = pcl::PointCloud<pcl::PointNormal>::Ptr;
OrientedKeypoints orientedKeypoints(const std::vector<Eigen::Vector3f>& points,
                                    const FeatureParams& params, const NormalSideTest& flip = {});

/// FPFH of oriented keypoints, those on structure kept: the costly part, needing no grid.
FeatureCloud describeOriented(const OrientedKeypoints& keypoints, const FeatureParams& params);

/// describeOriented(orientedKeypoints(points, params, flip), params).
FeatureCloud describe(const std::vector<Eigen::Vector3f>& points, const FeatureParams& params,
                      const NormalSideTest& flip = {});

}  // namespace socc::localization
