#include "socc/sim/path.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace socc::sim {

namespace {

constexpr double kSpacing = 0.25;  // [m] sampling of parametric curves

template <typename Curve>
std::vector<Eigen::Vector3d> sample(Curve curve, double u_end, std::size_t n) {
  std::vector<Eigen::Vector3d> pts;
  for (std::size_t i = 0; i <= n; ++i) pts.push_back(curve(u_end * static_cast<double>(i) / n));
  return pts;
}

std::size_t samplesFor(double length) {
  return std::max<std::size_t>(2, static_cast<std::size_t>(std::ceil(length / kSpacing)));
}

PathPoint between(const PathPoint& a, const PathPoint& b, double b_s, double s) {
  const double w = b_s > a.s ? (s - a.s) / (b_s - a.s) : 0.0;
  PathPoint p;
  p.position = (1 - w) * a.position + w * b.position;
  p.heading = a.heading + w * std::remainder(b.heading - a.heading, 2 * M_PI);
  p.s = s;
  return p;
}

}  // namespace

Eigen::Vector3d PathPoint::offset(double lateral) const {
  return position + lateral * Eigen::Vector3d(-std::sin(heading), std::cos(heading), 0.0);
}

Path::Path(const std::vector<Eigen::Vector3d>& points, bool closed) : closed_(closed) {
  if (points.size() < 2) throw std::invalid_argument("a path needs at least 2 points");
  double s = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (i > 0) s += (points[i] - points[i - 1]).head<2>().norm();
    points_.push_back({points[i], 0.0, s});
  }
  if (!(s > 0.0)) throw std::invalid_argument("a path must have a non-zero length");
  loop_length_ = closed ? s + (points.front() - points.back()).head<2>().norm() : s;
  // Tangents by central differences; a closed path's ends take their neighbours across the
  // seam, so that heading and position run on smoothly from one lap into the next.
  const std::size_t n = points_.size();
  for (std::size_t i = 0; i < n; ++i) {
    std::size_t a = i == 0 ? 0 : i - 1;
    std::size_t b = std::min(i + 1, n - 1);
    if (closed && i == 0) a = n - 1;
    if (closed && i == n - 1) b = 0;
    const Eigen::Vector3d d = points_[b].position - points_[a].position;
    points_[i].heading = std::atan2(d.y(), d.x());
  }
}

PathPoint Path::at(double s) const {
  if (closed_) {
    s = std::fmod(s, loop_length_);
    if (s < 0) s += loop_length_;
    // On the closing segment: from the last point back to the first.
    if (s >= points_.back().s) return between(points_.back(), points_.front(), loop_length_, s);
  } else {
    s = std::clamp(s, 0.0, length());
  }
  const auto it = std::upper_bound(points_.begin(), points_.end(), s,
                                   [](double v, const PathPoint& p) { return v < p.s; });
  if (it == points_.end()) return points_.back();
  if (it == points_.begin()) return points_.front();
  return between(*(it - 1), *it, it->s, s);
}

Path straightPath(double length, double z) {
  return Path(
      sample([&](double u) { return Eigen::Vector3d(u, 0, z); }, length, samplesFor(length)),
      false);
}

Path circlePath(double radius, double z) {
  const double len = 2 * M_PI * radius;
  auto pts = sample(
      [&](double u) {
        return Eigen::Vector3d(radius * std::sin(u), radius * (1 - std::cos(u)), z);
      },
      2 * M_PI, samplesFor(len));
  pts.pop_back();  // closed: the last point equals the first
  return Path(pts, true);
}

Path figureEightPath(double radius, double z) {
  // Two tangent circles: the left lobe counter-clockwise, then the right lobe clockwise.
  std::vector<Eigen::Vector3d> pts;
  const std::size_t n = samplesFor(2 * M_PI * radius);
  for (std::size_t i = 0; i < n; ++i) {
    const double u = 2 * M_PI * static_cast<double>(i) / n;
    pts.emplace_back(radius * std::sin(u), radius * (1 - std::cos(u)), z);
  }
  for (std::size_t i = 0; i < n; ++i) {
    const double u = 2 * M_PI * static_cast<double>(i) / n;
    pts.emplace_back(radius * std::sin(u), -radius * (1 - std::cos(u)), z);
  }
  return Path(pts, true);
}

Path zigzagPath(double length, double period, double z) {
  // asin(k sin(x)) is a triangle wave rounded at its corners for k < 1; the amplitude makes the
  // legs about 30 deg off the x axis.
  const double amplitude = std::tan(M_PI / 6) * period / 4;
  const double k = 0.97;
  return Path(sample(
                  [&](double u) {
                    const double y =
                        amplitude * (2 / M_PI) * std::asin(k * std::sin(2 * M_PI * u / period));
                    return Eigen::Vector3d(u, y, z);
                  },
                  length, samplesFor(length * 1.2)),
              false);
}

Path posePath(const Poses& poses, double margin) {
  std::vector<Eigen::Vector3d> pts;
  for (const auto& p : poses)
    if (pts.empty() || (p.translation() - pts.back()).head<2>().norm() > 0.2)
      pts.push_back(p.translation());
  if (pts.size() < 2) throw std::invalid_argument("the poses do not move: no path to build on");
  const auto extend = [&](const Eigen::Vector3d& end, const Eigen::Vector3d& before) {
    Eigen::Vector3d dir = end - before;
    dir.z() = 0;
    dir.normalize();
    std::vector<Eigen::Vector3d> ext;
    for (double d = 1.0; d <= margin; d += 1.0) ext.push_back(end + d * dir);
    return ext;
  };
  std::vector<Eigen::Vector3d> head = extend(pts.front(), pts[1]);
  std::vector<Eigen::Vector3d> tail = extend(pts.back(), pts[pts.size() - 2]);
  std::vector<Eigen::Vector3d> all(head.rbegin(), head.rend());
  all.insert(all.end(), pts.begin(), pts.end());
  all.insert(all.end(), tail.begin(), tail.end());
  return Path(all, false);
}

}  // namespace socc::sim
