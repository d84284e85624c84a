#include "hypothesis_search.hpp"

#include <pcl/registration/transformation_estimation_svd.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <optional>
#include <random>

namespace socc::localization {
namespace {

using Point = pcl::PointNormal;
using Cloud = pcl::PointCloud<Point>;

// Scan keypoints counted between two tests of a hypothesis' inlier share.
constexpr std::size_t kBlock = 64;
// A hypothesis is given up when its share so far lies this many standard deviations below the
// share it must reach (the keypoints counted are a binomial draw).
constexpr double kSigmas = 3.0;
// Scan keypoints tried as a sample's next point before the draw is given up.
constexpr int kPartnerAttempts = 16;
// Refinement of the kept hypotheses on their inliers (least squares, as LO-RANSAC does).
constexpr int kRefinements = 3;

bool sameHypothesis(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b,
                    const SearchParams& params) {
  const Eigen::Isometry3d d = a.inverse() * b;
  return d.translation().norm() < params.distinct_translation &&
         Eigen::AngleAxisd(d.linear()).angle() < params.distinct_rotation;
}

Eigen::Isometry3d toIsometry(const Eigen::Matrix4f& m) {
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.matrix() = m.cast<double>();
  return out;
}

class Search {
 public:
  Search(const IndexedFeatures& map, const FeatureCloud& scan, const SearchParams& params,
         const std::atomic<bool>* cancel)
      : map_(map),
        scan_(*scan.keypoints),
        scan_features_(*scan.features),
        params_(params),
        cancel_(cancel),
        rng_(params.seed),
        similar_(scan_.size()) {
    order_.resize(scan_.size());
    std::iota(order_.begin(), order_.end(), std::size_t{0});
    std::shuffle(order_.begin(), order_.end(), rng_);
    findSimilar();
  }

  std::vector<Hypothesis> run() {
    pcl::Indices source(3), target(3);
    for (; stats_.draws < params_.max_iterations && stats_.inlier_tests < params_.max_inlier_tests;
         ++stats_.draws) {
      if (cancel_ != nullptr && cancel_->load(std::memory_order_relaxed)) {
        stats_.cancelled = true;
        return {};
      }
      if (!drawSample(source, target)) continue;
      Eigen::Matrix4f m;
      svd_.estimateRigidTransformation(scan_, source, *map_.cloud.keypoints, target, m);
      consider(m);
    }
    for (Hypothesis& h : kept_) refine(h);
    return std::move(kept_);
  }

  const SearchStats& stats() const { return stats_; }

 private:
  const IndexedFeatures& map_;
  const Cloud& scan_;
  const pcl::PointCloud<pcl::FPFHSignature33>& scan_features_;
  const SearchParams& params_;
  const std::atomic<bool>* cancel_;  // may be null
  std::mt19937 rng_;
  std::vector<pcl::Indices> similar_;  // nearest map features of each scan keypoint
  std::vector<std::size_t> order_;     // the scan keypoints shuffled: blocks of it are fair draws
  std::vector<Hypothesis> kept_;       // best score first
  pcl::Indices consistent_;            // scratch: a partner's candidates that fit the sample
  pcl::registration::TransformationEstimationSVD<Point, Point> svd_;
  SearchStats stats_;

  // The nearest map features of every scan keypoint, in parallel: the draws of a full budget
  // touch nearly all of them, and these searches in 33 dimensions are a large part of a
  // request's cost. Each keypoint's list is the same however the work is split.
  void findSimilar() {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, scan_.size()),
                      [this](const tbb::blocked_range<std::size_t>& r) {
                        std::vector<float> distances;
                        for (std::size_t i = r.begin(); i != r.end(); ++i)
                          map_.features.nearestKSearch(scan_features_[i],
                                                       params_.correspondence_randomness,
                                                       similar_[i], distances);
                      });
  }

  const pcl::Indices& similarTo(int i) const { return similar_[static_cast<std::size_t>(i)]; }

  // A sample grown from one random correspondence (a scan keypoint and one of its nearest map
  // features): each further scan keypoint takes one of its candidates whose distances to the
  // map keypoints already chosen equal its own distances to their scan keypoints within
  // edge_tolerance (a rigid motion keeps distances). When the first pair is right, the partners
  // found are mostly right too, even where the descriptor ranks the right candidate far down:
  // the search needs one right pair in a draw, not three.
  bool drawSample(pcl::Indices& source, pcl::Indices& target) {
    std::uniform_int_distribution<int> pick(0, static_cast<int>(scan_.size()) - 1);
    source[0] = pick(rng_);
    const pcl::Indices& first = similarTo(source[0]);
    if (first.empty()) return false;
    target[0] = first[std::uniform_int_distribution<std::size_t>(0, first.size() - 1)(rng_)];
    for (std::size_t k = 1; k < 3; ++k)
      if (!addPartner(k, source, target)) return false;
    return true;
  }

  bool addPartner(std::size_t k, pcl::Indices& source, pcl::Indices& target) {
    std::uniform_int_distribution<int> pick(0, static_cast<int>(scan_.size()) - 1);
    const float min_edge = static_cast<float>(params_.min_edge);
    const auto tolerance = static_cast<float>(params_.edge_tolerance);
    const Cloud& map = *map_.cloud.keypoints;
    for (int attempt = 0; attempt < kPartnerAttempts; ++attempt) {
      const int j = pick(rng_);
      const Eigen::Vector3f pj = scan_[static_cast<std::size_t>(j)].getVector3fMap();
      std::array<float, 2> edges{};
      bool spread = true;
      for (std::size_t m = 0; m < k; ++m) {
        edges[m] = (pj - scan_[static_cast<std::size_t>(source[m])].getVector3fMap()).norm();
        spread = spread && edges[m] >= min_edge;
      }
      if (!spread) continue;
      consistent_.clear();
      for (const int b : similarTo(j)) {
        const Eigen::Vector3f qb = map[static_cast<std::size_t>(b)].getVector3fMap();
        bool fits = true;
        for (std::size_t m = 0; m < k && fits; ++m) {
          const float d = (qb - map[static_cast<std::size_t>(target[m])].getVector3fMap()).norm();
          fits = std::abs(d - edges[m]) <= tolerance;
        }
        if (fits) consistent_.push_back(b);
      }
      if (consistent_.empty()) continue;
      source[k] = j;
      target[k] =
          consistent_[std::uniform_int_distribution<std::size_t>(0, consistent_.size() - 1)(rng_)];
      return true;
    }
    return false;
  }

  // The map keypoint a scan keypoint lands within inlier_distance of at pose m, if any.
  std::optional<KeypointIndex::Nearest> inlier(const Eigen::Matrix4f& m, std::size_t i) const {
    const Eigen::Vector3f p =
        m.topLeftCorner<3, 3>() * scan_[i].getVector3fMap() + m.topRightCorner<3, 1>();
    const auto max2 = static_cast<float>(params_.inlier_distance * params_.inlier_distance);
    return map_.positions.nearestWithin(p, max2);
  }

  // All inliers of a pose, with their nearest map keypoints when matches is given.
  int inliers(const Eigen::Matrix4f& m, pcl::Correspondences* matches = nullptr) const {
    int count = 0;
    for (std::size_t i = 0; i < scan_.size(); ++i) {
      const auto near = inlier(m, i);
      if (!near) continue;
      ++count;
      if (matches) matches->emplace_back(static_cast<int>(i), near->index, near->squared_distance);
    }
    return count;
  }

  // The inliers of a pose counted in blocks of the shuffled keypoints; -1 as soon as the share
  // so far lies kSigmas standard deviations below need (most poses are given up after a block).
  int inliersAbove(const Eigen::Matrix4f& m, double need) {
    int count = 0;
    for (std::size_t done = 0; done < order_.size();) {
      const std::size_t end = std::min(order_.size(), done + kBlock);
      stats_.inlier_tests += static_cast<long long>(end - done);
      for (; done < end; ++done)
        if (inlier(m, order_[done])) ++count;
      if (done == order_.size()) break;
      const double n = static_cast<double>(done);
      if (count / n < need - kSigmas * std::sqrt(need * (1.0 - need) / n)) return -1;
    }
    return count;
  }

  // The inlier share a new hypothesis must reach to be kept.
  double bar() const {
    if (static_cast<int>(kept_.size()) < params_.keep) return params_.min_inlier_fraction;
    return std::max(params_.min_inlier_fraction, kept_.back().inlier_fraction);
  }

  void consider(const Eigen::Matrix4f& m) {
    const double need = bar();
    const int count = inliersAbove(m, need);
    if (count < 0) return;
    Hypothesis h;
    h.pose = toIsometry(m);
    h.inliers = count;
    h.inlier_fraction = static_cast<double>(count) / static_cast<double>(scan_.size());
    if (h.inlier_fraction < need) return;
    h.score = h.inlier_fraction;  // during the search; the free space is checked at the end
    offer(h);
  }

  void offer(const Hypothesis& h) {
    const auto same = [&](const Hypothesis& o) { return sameHypothesis(o.pose, h.pose, params_); };
    const auto it = std::find_if(kept_.begin(), kept_.end(), same);
    if (it != kept_.end()) {
      if (it->score >= h.score) return;
      kept_.erase(it);
    }
    const auto at = std::upper_bound(
        kept_.begin(), kept_.end(), h,
        [](const Hypothesis& a, const Hypothesis& b) { return a.score > b.score; });
    kept_.insert(at, h);
    if (static_cast<int>(kept_.size()) > params_.keep) kept_.pop_back();
  }

  // Least-squares pose on the hypothesis' inliers, repeated while it explains more of the scan.
  void refine(Hypothesis& h) const {
    Eigen::Matrix4f m = h.pose.matrix().cast<float>();
    for (int k = 0; k < kRefinements; ++k) {
      pcl::Correspondences matches;
      inliers(m, &matches);
      if (matches.size() < 3) return;
      Eigen::Matrix4f next;
      svd_.estimateRigidTransformation(scan_, *map_.cloud.keypoints, matches, next);
      const int count = inliers(next);
      if (count <= h.inliers) break;
      m = next;
      h.pose = toIsometry(m);
      h.inliers = count;
    }
    h.inlier_fraction = static_cast<double>(h.inliers) / static_cast<double>(scan_.size());
    h.score = h.inlier_fraction;  // until rankHypotheses weighs the free space
  }
};

}  // namespace

IndexedFeatures::IndexedFeatures(FeatureCloud c) : cloud(std::move(c)) {
  if (cloud.size() == 0) return;
  positions = KeypointIndex(cloud.keypoints);
  features.setInputCloud(cloud.features);
}

std::vector<Hypothesis> searchHypotheses(const IndexedFeatures& map, const FeatureCloud& scan,
                                         const SearchParams& params, SearchStats* stats,
                                         const std::atomic<bool>* cancel) {
  if (scan.size() < 3 || map.cloud.size() < 3) return {};
  Search search(map, scan, params, cancel);
  std::vector<Hypothesis> found = search.run();
  if (stats) *stats = search.stats();
  return found;
}

// Refinement may have brought two hypotheses together: one per place, best score first.
std::vector<Hypothesis> rankHypotheses(std::vector<Hypothesis> found, const ConflictAt& conflict,
                                       const SearchParams& params) {
  for (Hypothesis& h : found) {
    h.conflict = conflict ? conflict(h.pose) : 0.0;
    h.score = h.inlier_fraction - h.conflict;
  }
  std::sort(found.begin(), found.end(),
            [](const Hypothesis& a, const Hypothesis& b) { return a.score > b.score; });
  std::vector<Hypothesis> out;
  for (const Hypothesis& h : found) {
    const auto same = [&](const Hypothesis& o) { return sameHypothesis(o.pose, h.pose, params); };
    if (std::none_of(out.begin(), out.end(), same)) out.push_back(h);
  }
  return out;
}

}  // namespace socc::localization
