#include "bags/bag_packet_source.hpp"

#include <stdexcept>
#include <vector>

namespace socc::sensors::bags {

BagPacketSource::BagPacketSource(std::unique_ptr<BagReader> reader, std::size_t topic)
    : reader_(std::move(reader)) {
  const TopicInfo& info = reader_->topics().at(topic);
  kind_ = messageKind(info.type);
  if (kind_ == MessageKind::kUnsupported || kind_ == MessageKind::kPointCloud2 || !info.encoding) {
    throw std::invalid_argument("topic " + info.name + " (" + info.type + ") carries no packets");
  }
  encoding_ = *info.encoding;
  reader_->select(topic);
}

std::optional<Packet> BagPacketSource::next() {
  while (pending_.empty()) {
    std::optional<BagMessage> m = reader_->next();
    if (!m) return std::nullopt;
    std::vector<Packet> packets;
    try {
      appendPackets(kind_, ByteView(m->data), encoding_, m->stamp_ns, packets);
    } catch (const FormatError& e) {
      if (malformed_messages_++ == 0) first_error_ = e.what();
      continue;
    }
    pending_.insert(pending_.end(), std::make_move_iterator(packets.begin()),
                    std::make_move_iterator(packets.end()));
  }
  Packet p = std::move(pending_.front());
  pending_.pop_front();
  return p;
}

std::string BagPacketSource::problems() const {
  std::string p = reader_->problems();
  if (malformed_messages_ > 0) {
    p += std::to_string(malformed_messages_) +
         " malformed packet messages dropped (first: " + first_error_ + ")\n";
  }
  return p;
}

}  // namespace socc::sensors::bags
