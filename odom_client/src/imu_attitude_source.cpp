// A recording's IMU attitude as each scan's gravity reference (scan_source.hpp withImuAttitude):
// the orientation of the samples on either side of the scan's time, interpolated, gives the up
// direction in the IMU frame; the extrinsic rotation turns it into the sensor frame.
#include <cmath>
#include <iostream>
#include <limits>
#include <stdexcept>

#include "socc/odom/scan_source.hpp"

namespace socc::odom {
namespace {

constexpr std::int64_t kMaxGapNs = 100'000'000;       // IMUs publish at 50-400 Hz: wider is a gap
constexpr double kDefaultSigma = 0.5 * M_PI / 180.0;  // a MEMS AHRS's roll/pitch, when unstated

class ImuAttitudeSource final : public ScanSource {
 public:
  ImuAttitudeSource(std::unique_ptr<ScanSource> source, ImuAttitude imu)
      : source_(std::move(source)), imu_(std::move(imu)) {}

  std::optional<Scan> next() override {
    std::optional<Scan> scan = source_->next();
    if (!scan) {
      report();
      return scan;
    }
    ++scans_;
    if (!imu_.sensor_R_imu) imu_.sensor_R_imu = mounting(scan->frame_id);
    scan->gravity = attitudeAt(scan->utime * 1000);
    if (scan->gravity) ++referenced_;
    return scan;
  }

  std::size_t remaining() const override { return source_->remaining(); }
  std::string timing() const override { return source_->timing(); }
  bool live() const override { return source_->live(); }

 private:
  // sensor_R_imu from the recording's static transforms, by the frames' names.
  Eigen::Matrix3d mounting(const std::string& sensor_frame) {
    advanceTo(std::numeric_limits<std::int64_t>::min());  // the first sample names its frame
    if (!after_) return Eigen::Matrix3d::Identity();      // no attitude at all: report() says so
    const std::string imu_frame = after_->frame_id;
    std::optional<Eigen::Isometry3d> pose;
    if (!sensor_frame.empty() && !imu_frame.empty())
      pose = imu_.mounts.lookup(sensor_frame, imu_frame);
    if (!pose)
      throw std::runtime_error(
          "--imu-topic: the IMU's mounting in the LiDAR frame is not known: state imu_roll_deg, "
          "imu_pitch_deg and imu_yaw_deg in a --config file, or record /tf_static with a chain "
          "from the scans' frame (" +
          (sensor_frame.empty() ? std::string("they name none") : sensor_frame) +
          ") to the IMU's (" + (imu_frame.empty() ? std::string("none named") : imu_frame) +
          "); the recording's static transforms:\n" +
          (imu_.mounts.empty() ? std::string("  (none)\n") : imu_.mounts.describe()));
    const Eigen::Vector3d ypr = pose->linear().eulerAngles(2, 1, 0) * 180.0 / M_PI;
    std::cerr << "odom_client: IMU mounting from /tf_static: " << sensor_frame << " <- "
              << imu_frame << ", yaw " << ypr[0] << " pitch " << ypr[1] << " roll " << ypr[2]
              << " deg\n";
    return pose->linear();
  }

  // Moves the pair (before_, after_) of samples with an attitude on either side of t.
  void advanceTo(std::int64_t t) {
    while (!ended_ && (!after_ || after_->stamp_ns <= t)) {
      if (after_) before_ = after_;
      after_.reset();
      while (std::optional<sensors::ImuSample> s = imu_.stream->next()) {
        ++samples_;
        if (!s->orientation) {
          ++without_orientation_;
          continue;
        }
        if (first_ns_ < 0) first_ns_ = s->stamp_ns;
        last_ns_ = s->stamp_ns;
        after_ = std::move(s);
        break;
      }
      ended_ = !after_;
    }
  }

  std::optional<GravityReference> attitudeAt(std::int64_t t) {
    advanceTo(t);
    Eigen::Quaterniond q;
    const sensors::ImuSample* nearest = nullptr;
    if (before_ && t < before_->stamp_ns) return std::nullopt;  // scans out of time order
    if (before_ && after_ && after_->stamp_ns - before_->stamp_ns <= kMaxGapNs) {
      const double span = static_cast<double>(after_->stamp_ns - before_->stamp_ns);
      const double alpha = static_cast<double>(t - before_->stamp_ns) / span;
      q = before_->orientation->slerp(alpha, *after_->orientation);
      nearest = alpha < 0.5 ? &*before_ : &*after_;
    } else if (before_ && t - before_->stamp_ns <= kMaxGapNs / 10) {  // the IMU's last sample
      q = *before_->orientation;
      nearest = &*before_;
    } else {
      return std::nullopt;
    }
    GravityReference g;
    g.up = (*imu_.sensor_R_imu * (q.conjugate() * Eigen::Vector3d::UnitZ())).normalized();
    g.sigma = sigmaOf(*nearest);
    return g;
  }

  double sigmaOf(const sensors::ImuSample& s) const {
    if (imu_.sigma > 0.0) return imu_.sigma;
    const double roll = s.orientation_covariance(0, 0), pitch = s.orientation_covariance(1, 1);
    if (roll > 0.0 && pitch > 0.0 && std::isfinite(roll) && std::isfinite(pitch))
      return std::sqrt(std::max(roll, pitch));
    return kDefaultSigma;
  }

  void report() {
    if (reported_) return;
    reported_ = true;
    std::cerr << "odom_client: IMU attitude for " << referenced_ << " of " << scans_ << " scans ("
              << samples_ << " IMU samples";
    if (without_orientation_ > 0)
      std::cerr << ", " << without_orientation_ << " without an orientation";
    std::cerr << ")\n";
    if (referenced_ < scans_ && samples_ > without_orientation_)
      std::cerr << "odom_client: the IMU's attitude spans stamps " << first_ns_ << " .. "
                << last_ns_ << " ns: scans outside it, or more than 0.1 s between two samples, "
                << "have no gravity reference (do the LiDAR's and the IMU's clocks differ?)\n";
    if (samples_ > 0 && samples_ == without_orientation_)
      std::cerr << "odom_client: the IMU topic carries no orientation (orientation_covariance[0] "
                   "= -1): socc takes an IMU's attitude as its gravity reference, not its raw "
                   "accelerations\n";
    const std::string problems = imu_.stream->problems();
    if (!problems.empty()) std::cerr << "odom_client: IMU:\n" << problems;
  }

  std::unique_ptr<ScanSource> source_;
  ImuAttitude imu_;
  std::optional<sensors::ImuSample> before_, after_;
  bool ended_ = false, reported_ = false;
  std::int64_t first_ns_ = -1, last_ns_ = -1;
  std::size_t scans_ = 0, referenced_ = 0, samples_ = 0, without_orientation_ = 0;
};

}  // namespace

std::unique_ptr<ScanSource> withImuAttitude(std::unique_ptr<ScanSource> source, ImuAttitude imu) {
  return std::make_unique<ImuAttitudeSource>(std::move(source), std::move(imu));
}

}  // namespace socc::odom
