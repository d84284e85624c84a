#pragma once
// TEMPORARY (until the bag reader of #28 is merged): the VelodyneScan packets of a ROS 2 .db3 bag
// read straight from SQLite, so the VLP-32C test can run against nebula's reference before
// openRecording reads .db3 bags. Only used when openRecording reports that bags are not supported;
// delete with its use in test_velodyne_vlp32c.cpp once openBag is in.
#include <sqlite3.h>

#include <cstring>
#include <deque>
#include <filesystem>
#include <stdexcept>

#include "socc/sensors/packet.hpp"

namespace socc::sensors::test {

class TemporaryDb3Packets final : public PacketSource {
 public:
  explicit TemporaryDb3Packets(const std::filesystem::path& db3) {
    sqlite3* db = nullptr;
    if (sqlite3_open_v2(db3.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK) {
      sqlite3_close(db);
      throw std::runtime_error(db3.string() + ": cannot open");
    }
    sqlite3_stmt* st = nullptr;
    sqlite3_prepare_v2(db, "SELECT data FROM messages ORDER BY timestamp", -1, &st, nullptr);
    while (sqlite3_step(st) == SQLITE_ROW) {
      const auto* blob = static_cast<const std::uint8_t*>(sqlite3_column_blob(st, 0));
      parseScan(blob, static_cast<std::size_t>(sqlite3_column_bytes(st, 0)));
    }
    sqlite3_finalize(st);
    sqlite3_close(db);
  }
  std::optional<Packet> next() override {
    if (packets_.empty()) return std::nullopt;
    Packet p = std::move(packets_.front());
    packets_.pop_front();
    return p;
  }

 private:
  // CDR (little endian): 4-byte encapsulation, header {int32 sec, uint32 nanosec, string
  // frame_id}, then uint32 count of VelodynePacket {int32 sec, uint32 nanosec, uint8[1206]},
  // each aligned to 4 bytes from the start of the payload.
  void parseScan(const std::uint8_t* d, std::size_t n) {
    std::size_t at = 4;
    auto u32 = [&](std::size_t pos) {
      std::uint32_t v = 0;
      if (pos + 4 > n) throw std::runtime_error("short CDR message");
      std::memcpy(&v, d + pos, 4);
      return v;
    };
    auto align4 = [&] { at = 4 + ((at - 4 + 3) / 4) * 4; };
    at += 8;
    at += 4 + u32(at);  // frame_id
    align4();
    const std::uint32_t count = u32(at);
    at += 4;
    for (std::uint32_t i = 0; i < count; ++i) {
      align4();
      Packet p;
      p.stamp_ns = static_cast<std::int64_t>(static_cast<std::int32_t>(u32(at))) * 1'000'000'000 +
                   u32(at + 4);
      at += 8;
      if (at + 1206 > n) throw std::runtime_error("short CDR packet");
      p.data.assign(d + at, d + at + 1206);
      at += 1206;
      packets_.push_back(std::move(p));
    }
  }
  std::deque<Packet> packets_;
};

}  // namespace socc::sensors::test
