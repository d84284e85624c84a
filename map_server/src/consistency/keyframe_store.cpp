#include "keyframe_store.hpp"

#include <fcntl.h>
#include <unistd.h>
#include <zlib.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <string_view>

#include "byte_io.hpp"

namespace socc::consistency {
namespace {

constexpr std::string_view kMagic = "SOCC-CONSISTENCY-STORE\n";
constexpr std::uint32_t kFormatVersion = 1;
constexpr std::uint32_t kRecordMarker = 0x4b524353;  // "SCRK" little-endian
constexpr std::size_t kFrameHead = 4 + 1 + 8;        // marker, type, size
constexpr std::size_t kHeaderBytes = kMagic.size() + 4 + 1;

std::uint32_t checksum(RecordType type, const std::string& payload) {
  const auto t = static_cast<unsigned char>(type);
  uLong crc = crc32(0L, &t, 1);
  // zlib takes uInt lengths: feed a large payload in pieces.
  for (std::size_t at = 0; at < payload.size(); at += 1u << 30) {
    const std::size_t n = std::min<std::size_t>(payload.size() - at, 1u << 30);
    crc = crc32(crc, reinterpret_cast<const Bytef*>(payload.data() + at), static_cast<uInt>(n));
  }
  return static_cast<std::uint32_t>(crc);
}

void syncDirectoryOf(const std::filesystem::path& file) {
  const std::filesystem::path dir = file.parent_path();
  const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY);
  if (fd < 0) return;  // best effort, as the journal does
  ::fsync(fd);
  ::close(fd);
}

bool writeAll(std::FILE* out, const std::string& bytes, bool sync) {
  return std::fwrite(bytes.data(), 1, bytes.size(), out) == bytes.size() && std::fflush(out) == 0 &&
         (!sync || ::fdatasync(::fileno(out)) == 0);
}

std::FILE* openForAppend(const std::filesystem::path& file) {
  std::FILE* out = std::fopen(file.c_str(), "ab");
  if (out == nullptr)
    throw std::runtime_error("cannot open consistency store " + file.string() + ": " +
                             std::strerror(errno));
  return out;
}

void readHeader(std::istream& in, const std::filesystem::path& file, StoreContents& out) {
  std::string head(kHeaderBytes, '\0');
  if (!in.read(head.data(), static_cast<std::streamsize>(head.size())) ||
      head.compare(0, kMagic.size(), kMagic) != 0)
    throw std::runtime_error(file.string() + " is not a socc consistency store (bad header)");
  map::ByteReader r(head.data() + kMagic.size(), 5);
  const auto version = r.get<std::uint32_t>();
  if (version != kFormatVersion)
    throw std::runtime_error(file.string() + ": consistency store format version " +
                             std::to_string(version) + ", this map_server reads " +
                             std::to_string(kFormatVersion));
  out.foreign_base = r.get<std::uint8_t>() != 0;
  out.valid_bytes = kHeaderBytes;
}

void addRecord(RecordType type, const std::string& payload, StoreContents& out) {
  switch (type) {
    case RecordType::kKeyframe:
      out.keyframes.push_back(decodeKeyframe(payload));
      return;
    case RecordType::kClosure:
      out.closures.push_back(decodeClosure(payload));
      return;
    case RecordType::kRebuild:
      out.rebuilds.push_back(decodeRebuild(payload));
      return;
    case RecordType::kCheckpoint:
      out.checkpoints.push_back(decodeCheckpoint(payload));
      return;
    case RecordType::kWaiting:
      out.waiting.push_back(decodeWaiting(payload));
      return;
  }
  throw std::runtime_error("unknown record type " + std::to_string(static_cast<int>(type)));
}

// The next record into out; false at the clean end of the file. Throws what is wrong with it.
bool readRecord(std::istream& in, std::uint64_t file_size, StoreContents& out) {
  char head[kFrameHead];
  in.read(head, sizeof(head));
  if (in.gcount() == 0) return false;
  if (in.gcount() != static_cast<std::streamsize>(sizeof(head)))
    throw std::runtime_error("torn record header");
  map::ByteReader r(head, sizeof(head));
  if (r.get<std::uint32_t>() != kRecordMarker) throw std::runtime_error("no record marker");
  const auto type = static_cast<RecordType>(r.get<std::uint8_t>());
  const auto size = r.get<std::uint64_t>();
  if (size > file_size || size + 4 > file_size - out.valid_bytes - kFrameHead)
    throw std::runtime_error("torn record (" + std::to_string(size) + " bytes announced)");
  std::string payload(static_cast<std::size_t>(size), '\0');
  std::uint32_t crc = 0;
  if (!in.read(payload.data(), static_cast<std::streamsize>(size)) ||
      !in.read(reinterpret_cast<char*>(&crc), sizeof(crc)))
    throw std::runtime_error("torn record");
  if (crc != checksum(type, payload)) throw std::runtime_error("checksum mismatch");
  addRecord(type, payload, out);
  out.valid_bytes += kFrameHead + size + 4;
  return true;
}

}  // namespace

KeyframeStore::KeyframeStore(std::filesystem::path file, std::FILE* out, std::uint64_t bytes,
                             bool sync)
    : file_(std::move(file)), sync_(sync), out_(out), bytes_(bytes) {}

KeyframeStore::~KeyframeStore() {
  if (out_ != nullptr) std::fclose(out_);
}

std::unique_ptr<KeyframeStore> KeyframeStore::create(const std::filesystem::path& file,
                                                     bool foreign_base, bool sync) {
  // Beside the old store, then renamed over it: a crash leaves one whole header or the other.
  const std::filesystem::path tmp = file.string() + ".tmp";
  map::ByteWriter header;
  header.put<std::uint32_t>(kFormatVersion);
  header.put<std::uint8_t>(foreign_base ? 1 : 0);
  std::FILE* out = std::fopen(tmp.c_str(), "wb");
  const bool written = out != nullptr && writeAll(out, std::string(kMagic) + header.bytes(), true);
  if (out != nullptr) std::fclose(out);
  if (!written || ::rename(tmp.c_str(), file.c_str()) != 0)
    throw std::runtime_error("cannot write consistency store " + file.string() + ": " +
                             std::strerror(errno));
  syncDirectoryOf(file);
  return std::unique_ptr<KeyframeStore>(
      new KeyframeStore(file, openForAppend(file), kHeaderBytes, sync));
}

std::unique_ptr<KeyframeStore> KeyframeStore::resume(const std::filesystem::path& file,
                                                     const StoreContents& contents, bool sync) {
  std::error_code ec;
  if (std::filesystem::file_size(file, ec) != contents.valid_bytes) {
    std::filesystem::resize_file(file, contents.valid_bytes, ec);  // cut the dropped tail
    if (ec)
      throw std::runtime_error("cannot cut consistency store " + file.string() + ": " +
                               ec.message());
  }
  return std::unique_ptr<KeyframeStore>(
      new KeyframeStore(file, openForAppend(file), contents.valid_bytes, sync));
}

StoreContents KeyframeStore::read(const std::filesystem::path& file) {
  std::error_code ec;
  const std::uint64_t file_size = std::filesystem::file_size(file, ec);
  std::ifstream in(file, std::ios::binary);
  if (ec || !in) throw std::runtime_error("cannot read consistency store " + file.string());
  StoreContents out;
  readHeader(in, file, out);
  try {
    while (readRecord(in, file_size, out)) {
    }
  } catch (const std::exception& e) {
    out.problem = file.string() + ": dropped a torn or corrupt record at byte " +
                  std::to_string(out.valid_bytes) + " and the " +
                  std::to_string(file_size - out.valid_bytes) + " bytes after it (" + e.what() +
                  ")";
  }
  return out;
}

void KeyframeStore::add(RecordType type, const std::string& payload) {
  write(framed(type, payload));
}

void KeyframeStore::add(const std::vector<std::pair<RecordType, std::string>>& records) {
  std::string bytes;
  for (const auto& [type, payload] : records) bytes += framed(type, payload);
  if (!bytes.empty()) write(bytes);
}

std::string KeyframeStore::framed(RecordType type, const std::string& payload) {
  map::ByteWriter frame;
  frame.put<std::uint32_t>(kRecordMarker);
  frame.put<std::uint8_t>(static_cast<std::uint8_t>(type));
  frame.put<std::uint64_t>(payload.size());
  map::ByteWriter tail;
  tail.put<std::uint32_t>(checksum(type, payload));
  return frame.bytes() + payload + tail.bytes();
}

void KeyframeStore::write(const std::string& bytes) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (failed_) return;
  if (!writeAll(out_, bytes, sync_)) {
    failed_ = true;
    std::cerr << "map_server: consistency store " << file_.string() << " cannot be written ("
              << std::strerror(errno)
              << "): it keeps what it has; a restart will not rebuild the grid\n";
    return;
  }
  bytes_ += bytes.size();
}

bool KeyframeStore::failed() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return failed_;
}

std::uint64_t KeyframeStore::bytes() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return bytes_;
}

}  // namespace socc::consistency
