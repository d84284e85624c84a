#include "socc/sensors/decoded_scan_stream.hpp"

namespace socc::sensors {

DecodedScanStream::DecodedScanStream(std::unique_ptr<PacketSource> source,
                                     std::unique_ptr<ScanDecoder> decoder, std::string name)
    : source_(std::move(source)), decoder_(std::move(decoder)), name_(std::move(name)) {}

std::optional<SensorScan> DecodedScanStream::next() {
  while (ready_at_ >= ready_.size()) {
    ready_.clear();
    ready_at_ = 0;
    if (ended_) return std::nullopt;
    if (std::optional<Packet> p = source_->next()) {
      decoder_->feed(*p, ready_);
    } else {
      ended_ = true;
      decoder_->flush(ready_);
    }
  }
  SensorScan scan = std::move(ready_[ready_at_++]);
  scan.source = name_;
  return scan;
}

std::string DecodedScanStream::problems() const {
  std::string s = source_->problems();
  const std::string notes = decoder_->notes();
  if (!notes.empty()) s += name_ + ": " + notes + "\n";
  const std::string counts = describeDecodeStats(decoder_->stats());
  for (std::size_t at = 0; at < counts.size();) {
    const std::size_t end = counts.find('\n', at);
    s += name_ + ": " + counts.substr(at, end - at) + "\n";
    at = end == std::string::npos ? counts.size() : end + 1;
  }
  return s;
}

std::string describeDecodeStats(const DecodeStats& st) {
  std::string s;
  auto line = [&s](std::uint64_t n, const char* what) {
    if (n > 0) s += std::to_string(n) + " " + what + "\n";
  };
  line(st.other_sender, "packets of other senders on the port (dropped)");
  line(st.foreign, "packets of another model or not LiDAR data (skipped)");
  line(st.malformed, "malformed packets (skipped)");
  line(st.late, "late or duplicate packets (skipped)");
  line(st.gaps, "packets lost (gaps in the azimuth)");
  line(st.partial_scans, "incomplete sweeps (first / last of the recording, or lost packets)");
  return s;
}

}  // namespace socc::sensors
