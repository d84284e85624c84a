#include "socc/odom/range_calibration.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <stdexcept>

namespace socc::odom {
namespace {

constexpr double kDegrees = 180.0 / M_PI;
constexpr int kUnknowns = 3;  // per laser: range offset, range scale, azimuth
// [rad] the prior spread of a laser's azimuth offset (a nuisance unknown: a few tenths of a
// degree, more than factory calibrations leave).
constexpr double kAzimuthSpread = 0.005;
// The bin table's range of elevation tangents (+-71.6 deg; steeper points share the end bins)
// and its step (at most 0.006 deg of elevation).
constexpr float kMaxTangent = 3.f;
constexpr float kTangentStep = 1e-4f;

}  // namespace

RangeCalibration::RangeCalibration(const RangeCalibrationParams& params)
    : params_(params),
      laser_of_bin_(static_cast<std::size_t>(std::ceil(180.0 / params.bin_deg)) + 1, -1) {
  const auto slots = static_cast<std::size_t>(std::lround(2.0 * kMaxTangent / kTangentStep)) + 1;
  tangent_bins_.reserve(slots);
  for (std::size_t i = 0; i < slots; ++i) {
    const double elevation =
        std::atan(-kMaxTangent + (static_cast<double>(i) + 0.5) * kTangentStep);
    const int bin = static_cast<int>(std::floor((elevation * kDegrees + 90.0) / params.bin_deg));
    tangent_bins_.push_back(std::clamp(bin, 0, static_cast<int>(laser_of_bin_.size()) - 1));
  }
}

int RangeCalibration::binOf(const Eigen::Vector3f& p) const {
  // This runs for every point of every scan: the tangent of the elevation looked up in a table
  // instead of an arc tangent per point.
  const float horizontal = std::sqrt(p.x() * p.x() + p.y() * p.y());
  const float tangent =
      horizontal > 0.f ? p.z() / horizontal : (p.z() > 0.f ? kMaxTangent : -kMaxTangent);
  const float slot = std::clamp((tangent + kMaxTangent) / kTangentStep, 0.f,
                                static_cast<float>(tangent_bins_.size() - 1));
  return tangent_bins_[static_cast<std::size_t>(slot)];
}

int RangeCalibration::laserOf(int bin) {
  int& laser = laser_of_bin_[static_cast<std::size_t>(bin)];
  if (laser >= 0) return laser;
  laser = static_cast<int>(corrections_.size());
  corrections_.emplace_back(Eigen::Vector2d::Zero());
  const auto n = static_cast<Eigen::Index>(kUnknowns * corrections_.size());
  info_.conservativeResizeLike(Eigen::MatrixXd::Zero(n, n));
  evidence_.conservativeResizeLike(Eigen::VectorXd::Zero(n));
  return laser;
}

double RangeCalibration::rangeError(int laser, double range) const {
  if (laser < 0) return 0.0;
  const Eigen::Vector2d& c = corrections_[static_cast<std::size_t>(laser)];
  return c(0) + c(1) * range;
}

void RangeCalibration::apply(LabeledCloud& cloud) const {
  if (!fitted_) return;
  for (Eigen::Vector3f& p : cloud.points) {
    const double range = p.norm();
    if (range <= 0.0) continue;
    const double error = rangeError(laser_of_bin_[static_cast<std::size_t>(binOf(p))], range);
    if (error != 0.0) p *= static_cast<float>(1.0 - error / range);
  }
}

std::vector<RangeCalibration::Sample> RangeCalibration::collect(const Points& raw,
                                                                const Points& placed,
                                                                const Eigen::Isometry3d& pose,
                                                                const LocalMap& map) {
  std::vector<Sample> out;
  const std::size_t n = std::min(raw.size(), placed.size());
  const std::size_t stride =
      std::max<std::size_t>(1, n / std::max<std::size_t>(1, params_.samples));
  const Eigen::Matrix3d rotation = pose.linear();
  const double inv_size = 1.0 / params_.surface_size;
  const Eigen::Vector3d half_cell = Eigen::Vector3d::Constant(0.5 * params_.surface_size);
  for (std::size_t i = 0; i < n; i += stride) {
    const Eigen::Vector3d p = raw[i].cast<double>();
    const double range = p.norm();
    const double horizontal = p.head<2>().norm();
    if (range < params_.min_range || horizontal <= 0.0) continue;
    const Eigen::Vector3d q = pose * placed[i].cast<double>();
    const std::optional<Neighbor> hit = map.nearest(q, params_.max_distance);
    if (!hit) continue;
    const MapVoxel& v = map.voxel(hit->index);
    // A looser bound on one voxel than on a piece of wall: the voxels' normals lean with their
    // lasers' disagreement (two rings 0.14 m apart, 6 cm apart in range: 23 deg).
    if (!isPlanar(v, params_.planarity_threshold) ||
        std::abs(v.normal.z()) > 2.0 * params_.max_normal_z)
      continue;
    const Eigen::Vector3d ray = rotation * p;
    Eigen::Vector3d normal = v.normal.normalized();
    if (normal.dot(ray) > 0.0) normal = -normal;
    if (-normal.dot(ray) / range < params_.min_incidence) continue;
    if (std::abs(normal.dot(q - v.point)) > params_.max_residual) continue;
    const int laser = laserOf(binOf(raw[i]));
    const Eigen::Vector3d uncorrected = q + ray * (rangeError(laser, range) / range);
    // A piece of wall: a cell, and the facing in 16 sectors (walls are near vertical). Two
    // grids half a cell apart, so that lasers on either side of one grid's cell border still
    // meet in the other's cells.
    const int sector = static_cast<int>(std::floor((std::atan2(normal.y(), normal.x()) + M_PI) /
                                                   (2.0 * M_PI) * 16.0)) %
                       16;
    out.push_back({{voxelIndex(q, inv_size), voxelIndex(q + half_cell, inv_size)},
                   sector,
                   laser,
                   uncorrected,
                   v.point,
                   ray,
                   rotation * Eigen::Vector3d(-p.y(), p.x(), 0.0),
                   normal});
  }
  return out;
}

void RangeCalibration::observe(const Points& raw, const Points& placed,
                               const Eigen::Isometry3d& pose, const LocalMap& map) {
  const double fade = std::exp(-1.0 / params_.memory_frames);
  info_ *= fade;
  evidence_ *= fade;
  std::vector<Sample> found = collect(raw, placed, pose, map);
  accumulate(found);
  if (++frames_ % params_.fit_every == 0) fit();
}

void RangeCalibration::accumulate(std::vector<Sample>& found) {
  for (int grid = 0; grid < 2; ++grid) accumulate(found, grid);
}

void RangeCalibration::accumulate(std::vector<Sample>& found, int grid) {
  // The map only says where walls are and which way they face: its points came from whichever
  // lasers saw a wall first, each with its own error, so they are no common reference. Each
  // piece of wall's plane offset is therefore one more unknown, eliminated here (Schur
  // complement): within one piece only the differences between this scan's points count, i.e.
  // between its lasers, as in Levinson & Thrun's (RSS 2010) energy of two beams on one surface.
  const auto less = [grid](const Sample& a, const Sample& b) {
    if (a.cell[grid] != b.cell[grid]) return indexLess(a.cell[grid], b.cell[grid]);
    return a.sector < b.sector;
  };
  std::sort(found.begin(), found.end(), less);
  for (std::size_t begin = 0, end = 0; begin < found.size(); begin = end) {
    for (end = begin + 1; end < found.size() && !less(found[begin], found[end]); ++end) {
    }
    addSurface(found.begin() + static_cast<std::ptrdiff_t>(begin),
               found.begin() + static_cast<std::ptrdiff_t>(end));
  }
}

namespace {

double median(std::vector<double> values) {
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

}  // namespace

void RangeCalibration::addSurface(std::vector<Sample>::const_iterator begin,
                                  std::vector<Sample>::const_iterator end) {
  if (end - begin < 2) return;
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  for (auto s = begin; s != end; ++s) normal += s->normal;
  // One vertical plane for the piece: its offset cancels, not its normal. Vertical, because
  // lasers whose scales grow with their elevation lean every wall by the same angle: the map's
  // normals, made of those lasers' points, lean with them, and only gravity tells the two apart.
  normal.normalize();
  if (std::abs(normal.z()) > params_.max_normal_z) return;
  normal.z() = 0.0;
  normal.normalize();
  // One plane only: a car before a wall, facing the same way, is another (its map voxels are).
  std::vector<double> anchors, residuals;
  for (auto s = begin; s != end; ++s) {
    anchors.push_back(normal.dot(s->anchor));
    residuals.push_back(normal.dot(s->point));
  }
  const double anchor = median(anchors), level = median(residuals);
  std::vector<std::pair<int, Eigen::Vector3d>> sums;  // the gradient's sum by laser
  int kept = 0;
  double residual_sum = 0.0;
  for (auto s = begin; s != end; ++s) {
    const double residual = normal.dot(s->point);
    // The lasers' own errors part the points (and the map voxels) of one wall by up to
    // max_scale_error x range.
    const double range = s->ray.norm();
    const double tolerance = params_.max_step + params_.max_scale_error * range;
    if (std::abs(normal.dot(s->anchor) - anchor) > tolerance ||
        std::abs(residual - level) > tolerance)
      continue;
    const double along = normal.dot(s->ray) / range;
    const Eigen::Vector3d g(along, along * range, normal.dot(s->azimuth));
    const Eigen::Index at = kUnknowns * s->laser;
    info_.block<kUnknowns, kUnknowns>(at, at) += 0.5 * g * g.transpose();  // 0.5: two grids
    evidence_.segment<kUnknowns>(at) += 0.5 * g * residual;
    residual_sum += residual;
    ++kept;
    const auto same =
        std::find_if(sums.begin(), sums.end(), [&](const auto& e) { return e.first == s->laser; });
    if (same == sums.end())
      sums.emplace_back(s->laser, g);
    else
      same->second += g;
  }
  if (kept == 0) return;
  const double count = kept;
  for (const auto& [a, sum_a] : sums) {
    const Eigen::Index at = kUnknowns * a;
    evidence_.segment<kUnknowns>(at) -= 0.5 * sum_a * (residual_sum / count);
    for (const auto& [b, sum_b] : sums)
      info_.block<kUnknowns, kUnknowns>(at, kUnknowns * b) -=
          0.5 * sum_a * sum_b.transpose() / count;
  }
}

void RangeCalibration::fit() {
  const Eigen::Index n = info_.rows();
  if (n == 0) return;
  // Every laser is corrected by its posterior mean under the prior of the lasers' spread: a laser
  // seen little keeps near zero, a correction grows with its evidence. A cut-off (lasers
  // known to 0.05 %) switched lasers in and out as the evidence faded, which moved the scans'
  // geometry from frame to frame where few lasers see walls far away (indoors).
  const Eigen::Vector3d spread(params_.offset_spread, params_.scale_spread, kAzimuthSpread);
  const double weight = 1.0 / (params_.noise * params_.noise);
  Eigen::MatrixXd a = weight * info_;
  for (Eigen::Index i = 0; i < n; ++i) a(i, i) += 1.0 / std::pow(spread(i % kUnknowns), 2);
  const Eigen::VectorXd errors = Eigen::LLT<Eigen::MatrixXd>(a).solve(weight * evidence_);
  // The lasers' common errors scale and shift the world, which no comparison between lasers
  // sees: for the covariances they are held at zero by a stiff constraint on the sum of each
  // error over all lasers, so that a laser's covariance is that of its error relative to the
  // others. Not for the means: there the lasers seen least would absorb the others' sum (-0.5 %
  // of scale on lasers with no evidence, docs/robustness.md "Corrected where the evidence is").
  const double lasers = static_cast<double>(corrections_.size());
  for (int k = 0; k < kUnknowns; ++k) {
    const double stiff = 1e4 / std::pow(spread(k), 2) / lasers;
    for (Eigen::Index i = k; i < n; i += kUnknowns)
      for (Eigen::Index j = k; j < n; j += kUnknowns) a(i, j) += stiff;
  }
  const Eigen::LLT<Eigen::MatrixXd> solver(a);  // a is positive definite: the prior
  // Only each laser's own block of the covariance a^-1 = L^-T L^-1 is needed: products of the
  // columns of L^-1, one triangular solve instead of the whole inverse.
  const Eigen::MatrixXd inverse_factor = solver.matrixL().solve(Eigen::MatrixXd::Identity(n, n));
  const Eigen::VectorXd variance = inverse_factor.colwise().squaredNorm().transpose();
  // The corrections keep the lasers' mean weighted by how well each is known, not the plain
  // mean: the lasers that see the far walls best are those whose points put the walls into the
  // map, and the world's scale is theirs (a gauge on all lasers rescaled it by the errors of
  // lasers seen little).
  Eigen::Vector2d mean = Eigen::Vector2d::Zero(), weights = Eigen::Vector2d::Zero();
  for (Eigen::Index at = 0; at < n; at += kUnknowns)
    for (int k = 0; k < 2; ++k) {
      mean(k) += errors(at + k) / variance(at + k);
      weights(k) += 1.0 / variance(at + k);
    }
  mean = mean.cwiseQuotient(weights);
  // That shift of the world's reference is given to a laser only in what its own evidence
  // determines of its offset and scale (1 - posterior / prior covariance): a laser seen on almost
  // no wall keeps its factory calibration, one seen at one range alone takes the shift at that
  // range.
  const Eigen::Matrix2d prior_precision = spread.head<2>().cwiseAbs2().cwiseInverse().asDiagonal();
  for (std::size_t l = 0; l < corrections_.size(); ++l) {
    const auto at = static_cast<Eigen::Index>(kUnknowns * l);
    const auto columns = inverse_factor.middleCols<2>(at);
    const Eigen::Matrix2d determined =
        Eigen::Matrix2d::Identity() - columns.transpose() * columns * prior_precision;
    corrections_[l] = errors.segment<2>(at) - determined * mean;
  }
  fitted_ = true;
}

std::vector<RangeCalibration::Laser> RangeCalibration::lasers() const {
  std::vector<Laser> out;
  for (std::size_t b = 0; b < laser_of_bin_.size(); ++b) {
    const int laser = laser_of_bin_[b];
    if (laser < 0) continue;
    const Eigen::Vector2d& c = corrections_[static_cast<std::size_t>(laser)];
    out.push_back({(static_cast<double>(b) + 0.5) * params_.bin_deg - 90.0, c(0), c(1)});
  }
  return out;
}

void writeRangeCalibration(const std::string& path,
                           const std::vector<RangeCalibration::Laser>& lasers) {
  std::ofstream out(path);
  out << "# per-laser range calibration (odom_client, range_calibration: true): a laser's range r\n"
         "# is corrected to r - offset - scale * r; lasers not listed are not corrected\n"
         "# elevation_deg offset_m scale\n"
      << std::fixed;
  for (const RangeCalibration::Laser& l : lasers)
    out << std::setprecision(2) << l.elevation_deg << ' ' << std::setprecision(4) << l.offset << ' '
        << std::setprecision(6) << l.scale << '\n';
  if (!out) throw std::runtime_error("cannot write " + path);
}

}  // namespace socc::odom
