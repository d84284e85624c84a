// The pcap reader (libpcap + link / IPv4 / UDP / fragment parsing) on arbitrary files: it must
// return packets, end, or throw std::runtime_error.
#include <stdexcept>

#include "socc/sensors/pcap_source.hpp"
#include "temp_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const socc::fuzz::TempFile file(data, size, ".pcap");
  try {
    std::unique_ptr<socc::sensors::PacketSource> source = socc::sensors::openPcap(file.path(), 0);
    while (std::optional<socc::sensors::Packet> p = source->next())
      if (p->data.size() > 65535) std::abort();
    (void)source->problems();
  } catch (const std::runtime_error&) {
  }
  return 0;
}
