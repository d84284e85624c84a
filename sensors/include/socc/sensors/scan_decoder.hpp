#pragma once
// Packets of one sensor model -> sweeps. One implementation per vendor family (Velodyne,
// Ouster, Hesai); programs get one through make_decoder (sensor_config.hpp), never directly.
#include <cstdint>
#include <string>
#include <vector>

#include "socc/sensors/packet.hpp"
#include "socc/sensors/sensor_scan.hpp"

namespace socc::sensors {

/// Counts a decoder keeps; every packet it was fed is in exactly one of the first five.
struct DecodeStats {
  std::uint64_t packets = 0;        // decoded into points
  std::uint64_t other_sender = 0;   // from another address than the sensor's: dropped
  std::uint64_t foreign = 0;        // another model / not a data packet: skipped
  std::uint64_t malformed = 0;      // wrong size, bad header or values: skipped
  std::uint64_t late = 0;           // older than the sweep being built (reordered): skipped
  std::uint64_t gaps = 0;           // missing packets detected (from azimuth / sequence jumps)
  std::uint64_t scans = 0;          // sweeps produced
  std::uint64_t partial_scans = 0;  // of those, complete == false
};

class ScanDecoder {
 public:
  virtual ~ScanDecoder() = default;
  /// Decodes one UDP payload; every sweep it completes is appended to out.
  virtual void feed(const Packet& packet, std::vector<SensorScan>& out) = 0;
  /// End of input: the sweep under construction (complete == false) is appended, if kept.
  virtual void flush(std::vector<SensorScan>& out) = 0;
  virtual const DecodeStats& stats() const = 0;
  /// The model this decoder decodes, e.g. "vlp16".
  virtual std::string model() const = 0;
  /// What the decoder decided that the user should know (e.g. "factory byte 0x21 (hdl32e)
  /// disagrees with the packet timing: decoded as vlp16"); empty when nothing.
  virtual std::string notes() const { return {}; }
};

}  // namespace socc::sensors
