// sensor_msgs/Imu topics of bags as an ImuStream (socc/sensors/imu_stream.hpp).
#include <cmath>
#include <stdexcept>
#include <vector>

#include "bags/bag_reader.hpp"
#include "bags/ros_messages.hpp"
#include "socc/sensors/imu_stream.hpp"

namespace socc::sensors {
namespace {

// A quaternion whose norm is this far from 1 is not an orientation (e.g. all zeros from a driver
// that fills no attitude but does not say so with the covariance).
constexpr double kUnitTolerance = 0.1;

std::size_t chooseImuTopic(const bags::BagReader& reader, const std::string& requested,
                           const std::filesystem::path& bag) {
  const std::vector<bags::TopicInfo>& topics = reader.topics();
  std::vector<std::size_t> imu;
  for (std::size_t i = 0; i < topics.size(); ++i) {
    if (!bags::isImuType(topics[i].type) || !topics[i].encoding) continue;
    if (requested.empty() || topics[i].name == requested) imu.push_back(i);
  }
  if (imu.size() == 1) return imu[0];
  const std::string what = !requested.empty() ? "no sensor_msgs/Imu topic " + requested
                           : imu.empty()      ? "no sensor_msgs/Imu topic"
                                              : "several sensor_msgs/Imu topics, choose one";
  throw std::runtime_error(bag.string() + ": " + what + "; its topics:\n" +
                           bags::describeTopics(topics));
}

ImuSample toSample(const bags::ImuMsg& m) {
  ImuSample s;
  s.stamp_ns = m.header.stamp_ns;
  s.frame_id = m.header.frame_id;
  s.orientation_covariance = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(
      m.orientation_covariance.data());
  s.angular_velocity = Eigen::Vector3d(m.angular_velocity.data());
  s.linear_acceleration = Eigen::Vector3d(m.linear_acceleration.data());
  const Eigen::Quaterniond q(m.orientation[3], m.orientation[0], m.orientation[1],
                             m.orientation[2]);
  const bool stated = m.orientation_covariance[0] != -1.0;
  if (stated && q.coeffs().allFinite() && std::abs(q.norm() - 1.0) < kUnitTolerance)
    s.orientation = q.normalized();
  return s;
}

class BagImuStream final : public ImuStream {
 public:
  BagImuStream(std::unique_ptr<bags::BagReader> reader, std::size_t topic)
      : reader_(std::move(reader)), encoding_(*reader_->topics()[topic].encoding) {
    reader_->select(topic);
  }

  std::optional<ImuSample> next() override {
    while (std::optional<bags::BagMessage> m = reader_->next()) {
      try {
        return toSample(bags::parseImu(bags::ByteView(m->data), encoding_));
      } catch (const bags::FormatError& e) {
        if (malformed_++ == 0) first_error_ = e.what();
      }
    }
    return std::nullopt;
  }

  std::string problems() const override {
    std::string p = reader_->problems();
    if (malformed_ > 0)
      p += std::to_string(malformed_) + " malformed Imu messages dropped (first: " + first_error_ +
           ")\n";
    return p;
  }

 private:
  std::unique_ptr<bags::BagReader> reader_;
  bags::Encoding encoding_;
  std::uint64_t malformed_ = 0;
  std::string first_error_;
};

}  // namespace

std::unique_ptr<ImuStream> openImuTopic(const std::filesystem::path& bag,
                                        const std::string& topic) {
  std::unique_ptr<bags::BagReader> reader = bags::openBagReader(bag);
  const std::size_t index = chooseImuTopic(*reader, topic, bag);
  return std::make_unique<BagImuStream>(std::move(reader), index);
}

}  // namespace socc::sensors
