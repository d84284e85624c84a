#include "detecting_decoder.hpp"

#include "socc/sensors/hesai_decoder.hpp"
#include "velodyne/velodyne_decoder.hpp"

namespace socc::sensors {
namespace {

class DetectingDecoder final : public ScanDecoder {
 public:
  explicit DetectingDecoder(SensorConfig config) : config_(std::move(config)) {}

  void feed(const Packet& packet, std::vector<SensorScan>& out) override {
    if (!inner_) inner_ = decoderFor(packet);
    inner_->feed(packet, out);
  }
  void flush(std::vector<SensorScan>& out) override {
    if (inner_) inner_->flush(out);
  }
  const DecodeStats& stats() const override { return inner_ ? inner_->stats() : none_; }
  std::string model() const override { return inner_ ? inner_->model() : "(not detected yet)"; }
  std::string notes() const override { return inner_ ? inner_->notes() : std::string(); }

 private:
  std::unique_ptr<ScanDecoder> decoderFor(const Packet& packet) const {
    SensorConfig config = config_;
    config.model = detectHesaiModel(packet.data);
    if (!config.model.empty()) return makeHesaiDecoder(config);
    return velodyne::makeVelodyneDecoder(config_);
  }

  SensorConfig config_;
  std::unique_ptr<ScanDecoder> inner_;
  DecodeStats none_;
};

}  // namespace

std::unique_ptr<ScanDecoder> makeDetectingDecoder(const SensorConfig& config) {
  return std::make_unique<DetectingDecoder>(config);
}

}  // namespace socc::sensors
