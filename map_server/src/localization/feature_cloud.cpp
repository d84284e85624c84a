#include "feature_cloud.hpp"

#include <pcl/features/fpfh_omp.h>
#include <pcl/features/normal_3d_omp.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/search/kdtree.h>

#include <cmath>

namespace socc::localization {
namespace {

// PCL's OpenMP estimators: the machine budget is two cores.
constexpr unsigned kThreads = 2;

pcl::PointCloud<pcl::PointXYZ>::Ptr keypointsOf(const std::vector<Eigen::Vector3f>& points,
                                                double voxel) {
  pcl::PointCloud<pcl::PointXYZ>::Ptr raw(new pcl::PointCloud<pcl::PointXYZ>);
  raw->reserve(points.size());
  for (const Eigen::Vector3f& p : points) raw->push_back(pcl::PointXYZ(p.x(), p.y(), p.z()));
  pcl::PointCloud<pcl::PointXYZ>::Ptr out(new pcl::PointCloud<pcl::PointXYZ>);
  pcl::VoxelGrid<pcl::PointXYZ> grid;
  grid.setInputCloud(raw);
  const auto leaf = static_cast<float>(voxel);
  grid.setLeafSize(leaf, leaf, leaf);
  grid.filter(*out);
  return out;
}

pcl::PointCloud<pcl::PointNormal>::Ptr withNormals(
    const pcl::PointCloud<pcl::PointXYZ>::Ptr& keypoints, double radius,
    const NormalSideTest& flip) {
  pcl::PointCloud<pcl::Normal> normals;
  pcl::NormalEstimationOMP<pcl::PointXYZ, pcl::Normal> estimator(kThreads);
  estimator.setInputCloud(keypoints);
  estimator.setSearchMethod(
      pcl::search::KdTree<pcl::PointXYZ>::Ptr(new pcl::search::KdTree<pcl::PointXYZ>));
  estimator.setRadiusSearch(radius);
  estimator.setViewPoint(0.f, 0.f, 0.f);
  estimator.compute(normals);
  pcl::PointCloud<pcl::PointNormal>::Ptr out(new pcl::PointCloud<pcl::PointNormal>);
  out->reserve(keypoints->size());
  for (std::size_t i = 0; i < keypoints->size(); ++i) {
    Eigen::Vector3f n = normals[i].getNormalVector3fMap();
    if (!n.allFinite()) continue;
    const Eigen::Vector3f p = (*keypoints)[i].getVector3fMap();
    if (flip && flip(p, n)) n = -n;
    pcl::PointNormal q;
    q.getVector3fMap() = p;
    q.getNormalVector3fMap() = n;
    q.curvature = normals[i].curvature;
    out->push_back(q);
  }
  return out;
}

bool finiteHistogram(const pcl::FPFHSignature33& f) {
  float sum = 0.f;
  for (const float v : f.histogram) {
    if (!std::isfinite(v)) return false;
    sum += v;
  }
  return sum > 0.f;
}

}  // namespace

OrientedKeypoints orientedKeypoints(const std::vector<Eigen::Vector3f>& points,
                                    const FeatureParams& params, const NormalSideTest& flip) {
  if (points.empty()) return OrientedKeypoints(new pcl::PointCloud<pcl::PointNormal>);
  return withNormals(keypointsOf(points, params.keypoint_voxel), params.normal_radius, flip);
}

FeatureCloud describeOriented(const OrientedKeypoints& keypoints, const FeatureParams& params) {
  FeatureCloud out;
  if (!keypoints || keypoints->empty()) return out;
  pcl::PointCloud<pcl::FPFHSignature33> features;
  pcl::FPFHEstimationOMP<pcl::PointNormal, pcl::PointNormal, pcl::FPFHSignature33> fpfh(kThreads);
  fpfh.setInputCloud(keypoints);
  fpfh.setInputNormals(keypoints);
  fpfh.setSearchMethod(
      pcl::search::KdTree<pcl::PointNormal>::Ptr(new pcl::search::KdTree<pcl::PointNormal>));
  fpfh.setRadiusSearch(params.feature_radius);
  fpfh.compute(features);
  for (std::size_t i = 0; i < keypoints->size(); ++i) {
    if (!finiteHistogram(features[i]) || (*keypoints)[i].curvature < params.min_curvature) continue;
    out.keypoints->push_back((*keypoints)[i]);
    out.features->push_back(features[i]);
  }
  return out;
}

FeatureCloud describe(const std::vector<Eigen::Vector3f>& points, const FeatureParams& params,
                      const NormalSideTest& flip) {
  return describeOriented(orientedKeypoints(points, params, flip), params);
}

}  // namespace socc::localization
