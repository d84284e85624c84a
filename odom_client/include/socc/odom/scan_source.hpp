#pragma once
// Where scans come from: a KITTI-layout directory, a directory of PCD/PLY files, a recording
// (pcap capture or ROS bag, through socc_sensors) or a live LCM channel (socc::scan_t on
// SOCC/SCAN/<robot_id>, e.g. replayed by lcm-logplayer or published by socc-lidar).
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "socc/gravity_reference.hpp"
#include "socc/point_cloud.hpp"
#include "socc/sensors/imu_stream.hpp"
#include "socc/sensors/recording.hpp"
#include "socc/sensors/static_transforms.hpp"

namespace socc::odom {

struct Scan {
  LabeledCloud cloud;      // sensor frame; labels are class ids 0..19
  std::int64_t utime = 0;  // scan time [us]
  std::int64_t seq = 0;    // frame index (directories) or the driver's sequence number (LCM)
  std::string name;        // for messages, e.g. the file name
  std::string frame_id;    // the sensor frame's name where the source has one (PointCloud2)
  /// The up direction in the sensor frame at utime, from the source's IMU/INS (a KITTI
  /// directory's gravity.txt); none: the source has no gravity reference for this scan.
  std::optional<GravityReference> gravity = std::nullopt;
};

class ScanSource {
 public:
  virtual ~ScanSource() = default;
  /// The next scan, or nullopt at the end (directories) / after the idle timeout (LCM).
  /// Throws std::runtime_error with the file name on unreadable input.
  virtual std::optional<Scan> next() = 0;
  /// Scans left, when known (0 = unknown, live input).
  virtual std::size_t remaining() const = 0;
  /// Where the scans' time stamps come from, or what was assumed in their place (printed at
  /// start-up: speeds and accelerations in frames.csv follow from it).
  virtual std::string timing() const { return "the scans' own time stamps"; }
  /// Scans arrive at the sensor's pace whether or not they are taken (a live channel): what
  /// blocks the scan loop loses scans. Files wait for their reader.
  virtual bool live() const { return false; }
};

struct FrameRange {
  std::int64_t first = 0;  // first frame index to read
  std::int64_t last = -1;  // last frame index (inclusive); -1 = until the end
};

/// velodyne/*.bin, optional labels/*.label (raw SemanticKITTI ids, mapped), optional times.txt
/// (scan times [s]; without it frame k is at k * frame_period), point_times/NNNNNN.bin
/// (float32 per-point times [s]) and gravity.txt (the up direction per frame,
/// socc/gravity_file.hpp; line k is frame k, like times.txt).
std::unique_ptr<ScanSource> openKittiDirectory(const std::filesystem::path& root, FrameRange range,
                                               double frame_period = 0.1);

/// Sorted *.pcd / *.ply files of a directory; the frame index is the position in that order.
/// Scan times from the file names when every name holds one (file_name_stamps.hpp), else frame
/// k at k * frame_period.
std::unique_ptr<ScanSource> openPointCloudDirectory(const std::filesystem::path& dir,
                                                    FrameRange range, double frame_period);

/// A pcap capture or a bag (sensors::openRecording): one scan per sweep, with the sensor's
/// per-point times; the frame index is the sweep's index. Problems of the recording (lost or
/// foreign packets, damaged records) are reported on stderr at its end.
std::unique_ptr<ScanSource> openRecordingScans(const std::filesystem::path& file,
                                               const sensors::RecordingOptions& options,
                                               FrameRange range);

/// A recording's IMU attitude as the scans' gravity reference (odom_client/README.md "Gravity
/// reference"): the IMU's orientation interpolated at each scan's time, its up direction turned
/// into the sensor frame.
struct ImuAttitude {
  std::unique_ptr<sensors::ImuStream> stream;
  /// The IMU's axes in the sensor frame; none: from mounts, by the scans' and the IMU samples'
  /// frame names (a recording's /tf_static).
  std::optional<Eigen::Matrix3d> sensor_R_imu;
  sensors::StaticTransforms mounts;
  double sigma = 0.0;  // [rad] per tilt component; 0: the samples' covariance, or 0.5 deg
};

/// source's scans, each with the gravity reference of imu at its time (none where the IMU has
/// no attitude within 0.1 s of it: counted, and reported on stderr at the end). Throws
/// std::runtime_error at the first scan when the mounting is neither given nor found in mounts.
std::unique_ptr<ScanSource> withImuAttitude(std::unique_ptr<ScanSource> source, ImuAttitude imu);

/// source, read one scan ahead in a worker thread: the next file is read while the current scan
/// is registered. For directories; a live source buffers what arrives anyway.
std::unique_ptr<ScanSource> readAhead(std::unique_ptr<ScanSource> source);

/// source replayed at rate times the pace of its scans' time stamps (--rate): scan k is handed
/// out no earlier than (utime_k - utime_0) / rate after the first, as a sensor would deliver it;
/// a scan the loop asks for late is given at once, not dropped (the count and the largest delay
/// are reported on stderr). live() is true: what blocks the scan loop does not stop the clock.
/// Throws std::invalid_argument unless rate > 0.
std::unique_ptr<ScanSource> atRecordedPace(std::unique_ptr<ScanSource> source, double rate);

/// Subscribes to SOCC/SCAN/<robot_id>; next() waits up to idle_timeout for a scan. Scans are
/// not signed: lcm_url must stay on this machine (ttl=0 or memq://; throws otherwise).
/// Malformed scans (sizes, labels) are reported on stderr and skipped.
std::unique_ptr<ScanSource> openLcmScans(const std::string& lcm_url, const std::string& robot_id,
                                         std::chrono::milliseconds idle_timeout);

}  // namespace socc::odom
