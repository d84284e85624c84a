#include "localize_search.hpp"

#include <algorithm>

namespace socc::localization {
namespace {

// The map keypoints a scan seen from within the hint can overlap.
FeatureCloud nearHint(const FeatureCloud& map, const LocalizeHint& hint, double reach) {
  FeatureCloud out;
  for (std::size_t i = 0; i < map.size(); ++i) {
    const Eigen::Vector3d p = (*map.keypoints)[i].getVector3fMap().cast<double>();
    if ((p - hint.position).norm() > hint.radius + reach) continue;
    out.keypoints->push_back((*map.keypoints)[i]);
    out.features->push_back((*map.features)[i]);
  }
  return out;
}

double reachOf(const FeatureCloud& scan) {
  double reach = 0.0;
  for (const pcl::PointNormal& p : *scan.keypoints)
    reach = std::max(reach, static_cast<double>(p.getVector3fMap().norm()));
  return reach;
}

}  // namespace

void LocalizeSearch::run(const std::atomic<bool>* cancel) {
  found_.clear();
  const IndexedFeatures* map = map_ ? &map_->get() : nullptr;
  answer_.map_keypoints = map ? map->cloud.size() : 0;
  // Nothing to match against: the scan's descriptors (most of a search's cost on a small map)
  // are not computed. Robots in their own frame ask an empty map this every few scans.
  if (answer_.map_keypoints < 3) return;
  const FeatureCloud source = describe(scan_, params_.features);
  answer_.scan_keypoints = source.size();
  if (source.size() < 3) return;
  if (hint_) {
    // Only the map a scan from within the hint can see: a smaller feature tree, fewer lookalikes.
    const IndexedFeatures target(nearHint(map->cloud, *hint_, reachOf(source)));
    if (target.cloud.size() < 3) return;
    found_ = searchHypotheses(target, source, params_.search, &answer_.search, cancel);
  } else {
    found_ = searchHypotheses(*map, source, params_.search, &answer_.search, cancel);
  }
}

}  // namespace socc::localization
