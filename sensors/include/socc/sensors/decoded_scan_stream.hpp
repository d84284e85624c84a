#pragma once
// A packet source and a decoder as one scan stream: packets are read until the decoder completes
// a sweep; at the end of the packets the decoder is flushed.
#include <deque>
#include <memory>
#include <string>

#include "socc/sensors/packet.hpp"
#include "socc/sensors/scan_decoder.hpp"
#include "socc/sensors/sensor_scan.hpp"

namespace socc::sensors {

class DecodedScanStream final : public ScanStream {
 public:
  /// name: what the scans' `source` field says, e.g. "pcap vlp16.pcap".
  DecodedScanStream(std::unique_ptr<PacketSource> source, std::unique_ptr<ScanDecoder> decoder,
                    std::string name);
  std::optional<SensorScan> next() override;
  /// The source's problems and the decoder's counts of skipped packets and lost ones.
  std::string problems() const override;
  const ScanDecoder& decoder() const { return *decoder_; }

 private:
  std::unique_ptr<PacketSource> source_;
  std::unique_ptr<ScanDecoder> decoder_;
  std::string name_;
  std::vector<SensorScan> ready_;
  std::size_t ready_at_ = 0;
  bool ended_ = false;
};

/// The decoder's counts as text, one line per kind that is not zero ("12 packets lost").
std::string describeDecodeStats(const DecodeStats& stats);

}  // namespace socc::sensors
