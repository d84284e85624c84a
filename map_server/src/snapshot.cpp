// Snapshot file: header {magic "SOCCGRID", format version, payload size, CRC32 of payload,
// CRC32 of the header}, then the payload {config, map version, metadata blob, blocks in key
// order}. Written to a temp file in the same directory, fsynced and renamed (atomic); loaded
// fully into a new map and verified before anything is returned.
#include <fcntl.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <set>
#include <stdexcept>

#include "byte_io.hpp"
#include "map_impl.hpp"

namespace socc::map {
namespace {

constexpr char kMagic[8] = {'S', 'O', 'C', 'C', 'G', 'R', 'I', 'D'};
constexpr std::uint32_t kFormatVersion = 1;
constexpr std::size_t kHeaderSize = 32;

std::uint32_t crc(const char* data, std::size_t size) {
  uLong c = crc32(0L, Z_NULL, 0);
  // zlib takes uInt lengths: feed large payloads in pieces.
  while (size > 0) {
    const uInt n = static_cast<uInt>(std::min<std::size_t>(size, 1u << 30));
    c = crc32(c, reinterpret_cast<const Bytef*>(data), n);
    data += n;
    size -= n;
  }
  return static_cast<std::uint32_t>(c);
}

void writeConfig(ByteWriter& w, const MapConfig& c) {
  w.put(c.voxel_size);
  w.put(c.max_range);
  w.put(c.min_range);
  w.put<std::uint8_t>(c.raycast ? 1 : 0);
  w.put<std::uint8_t>(c.semantics ? 1 : 0);
  w.put(c.p_hit);
  w.put(c.p_miss);
  w.put(c.p_miss_static);
  w.put(c.p_miss_moving);
  w.put(c.clamp_min);
  w.put(c.clamp_max);
  w.put(c.occupancy_threshold);
  w.put(c.ema_alpha);
  w.put<std::uint64_t>(c.max_points_per_scan);
  w.put(c.max_abs_coordinate);
}

MapConfig readConfig(ByteReader& r) {
  MapConfig c;
  c.voxel_size = r.get<double>();
  c.max_range = r.get<double>();
  c.min_range = r.get<double>();
  c.raycast = r.get<std::uint8_t>() != 0;
  c.semantics = r.get<std::uint8_t>() != 0;
  c.p_hit = r.get<double>();
  c.p_miss = r.get<double>();
  c.p_miss_static = r.get<double>();
  c.p_miss_moving = r.get<double>();
  c.clamp_min = r.get<double>();
  c.clamp_max = r.get<double>();
  c.occupancy_threshold = r.get<double>();
  c.ema_alpha = r.get<double>();
  c.max_points_per_scan = static_cast<std::size_t>(r.get<std::uint64_t>());
  c.max_abs_coordinate = r.get<double>();
  if (const std::string err = validate(c); !err.empty())
    throw std::runtime_error("stored config is invalid: " + err);
  return c;
}

void writeStats(ByteWriter& w, const VoxelStats& s) {
  for (const float v : s.mean) w.put(v);
  for (const float v : s.m2) w.put(v);
  for (const float v : s.first_point) w.put(v);
  w.put(s.count);
  for (const std::uint16_t p : s.class_prob) w.put(p);
  w.put(s.label);
  w.put<std::uint8_t>(s.has_semantics ? 1 : 0);
}

VoxelStats readStats(ByteReader& r) {
  VoxelStats s;
  bool finite = true;
  for (float& v : s.mean) finite &= std::isfinite(v = r.get<float>());
  for (float& v : s.m2) finite &= std::isfinite(v = r.get<float>());
  for (float& v : s.first_point) finite &= std::isfinite(v = r.get<float>());
  s.count = r.get<std::uint32_t>();
  for (std::uint16_t& p : s.class_prob) p = r.get<std::uint16_t>();
  s.label = r.get<std::uint8_t>();
  s.has_semantics = r.get<std::uint8_t>() != 0;
  if (!finite) throw std::runtime_error("non-finite voxel statistics");
  if (s.count == 0) throw std::runtime_error("voxel statistics with zero points");
  if (!isValidClass(s.label)) throw std::runtime_error("voxel label out of range");
  return s;
}

void writeAll(int fd, const std::string& bytes, const std::string& what) {
  const char* p = bytes.data();
  std::size_t left = bytes.size();
  while (left > 0) {
    const ssize_t n = ::write(fd, p, left);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) throw std::runtime_error("cannot write " + what + ": " + std::strerror(errno));
    p += n;
    left -= static_cast<std::size_t>(n);
  }
}

/// Writes bytes to file atomically: temp file in the same directory, fsync, rename, fsync dir.
void writeFileAtomically(const std::filesystem::path& file, const std::string& bytes) {
  const std::filesystem::path dir =
      file.has_parent_path() ? file.parent_path() : std::filesystem::path(".");
  const std::filesystem::path tmp =
      dir / ("." + file.filename().string() + ".tmp." + std::to_string(::getpid()));
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0)
    throw std::runtime_error("cannot create " + tmp.string() + ": " + std::strerror(errno));
  try {
    writeAll(fd, bytes, tmp.string());
    if (::fsync(fd) != 0)
      throw std::runtime_error("cannot fsync " + tmp.string() + ": " + std::strerror(errno));
  } catch (...) {
    ::close(fd);
    ::unlink(tmp.c_str());
    throw;
  }
  if (::close(fd) != 0 || ::rename(tmp.c_str(), file.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    ::unlink(tmp.c_str());
    throw std::runtime_error("cannot write snapshot " + file.string() + ": " + reason);
  }
  if (const int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC); dfd >= 0) {
    ::fsync(dfd);  // make the rename itself durable
    ::close(dfd);
  }
}

/// The whole snapshot file (header + payload) once its header and payload checksums, format
/// version and size are verified; throws std::runtime_error prefixed by where otherwise.
std::string readVerifiedSnapshot(const std::filesystem::path& file, const std::string& where) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error(where + "cannot open (missing or unreadable)");
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw std::runtime_error(where + "read error");
  if (bytes.size() < kHeaderSize) throw std::runtime_error(where + "too short for a header");
  if (std::memcmp(bytes.data(), kMagic, sizeof(kMagic)) != 0)
    throw std::runtime_error(where + "not a socc map snapshot (bad magic)");
  ByteReader hr(bytes.data() + sizeof(kMagic), kHeaderSize - sizeof(kMagic));
  const auto version = hr.get<std::uint32_t>();
  hr.get<std::uint32_t>();
  const auto payload_size = hr.get<std::uint64_t>();
  const auto payload_crc = hr.get<std::uint32_t>();
  const auto header_crc = hr.get<std::uint32_t>();
  if (crc(bytes.data(), kHeaderSize - 4) != header_crc)
    throw std::runtime_error(where + "header checksum mismatch (corrupt file)");
  if (version != kFormatVersion)
    throw std::runtime_error(where + "unsupported format version " + std::to_string(version) +
                             " (expected " + std::to_string(kFormatVersion) + ")");
  if (payload_size != bytes.size() - kHeaderSize)
    throw std::runtime_error(where + "size mismatch (truncated or extended file)");
  if (crc(bytes.data() + kHeaderSize, payload_size) != payload_crc)
    throw std::runtime_error(where + "payload checksum mismatch (corrupt file)");
  return bytes;
}

/// Reads one block as save() writes it into grid; coord_limit bounds |key| in voxels.
void readBlock(ByteReader& r, double coord_limit, Grid& grid) {
  BlockKey key;
  for (int i = 0; i < 3; ++i) key[i] = r.get<std::int32_t>();
  if ((key.cast<double>().cwiseAbs().array() * kBlockDim > coord_limit + kBlockDim).any())
    throw std::runtime_error("block coordinate out of range");
  if (grid.find(key) != nullptr) throw std::runtime_error("duplicate block");
  Block& b = grid.getOrCreate(key);
  for (int word = 0; word < kBlockVoxels / 64; ++word) {
    const auto bits = r.get<std::uint64_t>();
    for (int j = 0; j < 64; ++j) b.observed[word * 64 + j] = ((bits >> j) & 1u) != 0;
  }
  for (int local = 0; local < kBlockVoxels; ++local) {
    if (!b.observed[local]) continue;
    const auto l = r.get<float>();
    if (!std::isfinite(l)) throw std::runtime_error("non-finite log-odds");
    b.log_odds[local] = l;
  }
  const auto with_stats = r.get<std::uint32_t>();
  if (with_stats > kBlockVoxels) throw std::runtime_error("too many statistics in a block");
  for (std::uint32_t k = 0; k < with_stats; ++k) {
    const auto local = r.get<std::uint16_t>();
    if (local >= kBlockVoxels || !b.observed[local] || b.statsOf(local) != nullptr)
      throw std::runtime_error("statistics for an invalid voxel");
    b.acquireStats(local) = readStats(r);
  }
}

}  // namespace

void SemanticOccupancyMap::save(const std::filesystem::path& file,
                                const std::string& metadata) const {
  const Impl& m = *impl_;
  ByteWriter w;
  writeConfig(w, m.config);
  w.put<std::int64_t>(m.version);
  w.putBytes(metadata);
  std::vector<BlockKey> keys;
  keys.reserve(m.grid.numBlocks());
  for (const auto& [key, block] : m.grid.blocks()) keys.push_back(key);
  std::sort(keys.begin(), keys.end(), indexLess);  // deterministic files
  w.put<std::uint64_t>(keys.size());
  for (const BlockKey& key : keys) {
    const Block& b = *m.grid.find(key);
    for (int i = 0; i < 3; ++i) w.put<std::int32_t>(key[i]);
    for (int word = 0; word < kBlockVoxels / 64; ++word) {
      std::uint64_t bits = 0;
      for (int j = 0; j < 64; ++j)
        if (b.observed[word * 64 + j]) bits |= std::uint64_t{1} << j;
      w.put(bits);
    }
    std::uint32_t with_stats = 0;
    for (int local = 0; local < kBlockVoxels; ++local) {
      if (!b.observed[local]) continue;
      w.put(b.log_odds[local]);
      with_stats += b.statsOf(local) != nullptr ? 1 : 0;
    }
    w.put(with_stats);
    for (int local = 0; local < kBlockVoxels; ++local) {
      if (const VoxelStats* s = b.statsOf(local)) {
        w.put<std::uint16_t>(static_cast<std::uint16_t>(local));
        writeStats(w, *s);
      }
    }
  }

  const std::string& payload = w.bytes();
  ByteWriter h;
  for (const char c : kMagic) h.put(c);
  h.put(kFormatVersion);
  h.put<std::uint32_t>(0);  // reserved
  h.put<std::uint64_t>(payload.size());
  h.put(crc(payload.data(), payload.size()));
  h.put(crc(h.bytes().data(), h.bytes().size()));
  writeFileAtomically(file, h.bytes() + payload);
}

SemanticOccupancyMap SemanticOccupancyMap::load(const std::filesystem::path& file,
                                                std::string* metadata) {
  const std::string where = "snapshot " + file.string() + ": ";
  const std::string bytes = readVerifiedSnapshot(file, where);
  try {
    ByteReader r(bytes.data() + kHeaderSize, bytes.size() - kHeaderSize);
    SemanticOccupancyMap map(readConfig(r));
    Impl& m = *map.impl_;
    m.version = r.get<std::int64_t>();
    std::string meta = r.getBytes();
    const auto num_blocks = r.get<std::uint64_t>();
    // Every block takes at least 48 bytes: a lying count fails here, not in an allocation.
    if (num_blocks > r.remaining() / 48) throw std::runtime_error("block count exceeds file size");
    const double limit = (m.config.max_abs_coordinate + m.config.max_range) / m.config.voxel_size;
    for (std::uint64_t n = 0; n < num_blocks; ++n) readBlock(r, limit, m.grid);
    if (r.remaining() != 0) throw std::runtime_error("trailing bytes");
    m.recount();
    if (metadata != nullptr) *metadata = std::move(meta);
    return map;
  } catch (const std::exception& e) {
    throw std::runtime_error(where + "corrupt payload: " + e.what());
  }
}

}  // namespace socc::map
