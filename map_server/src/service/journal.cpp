#include "journal.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <lcm/lcm-cpp.hpp>
#include <stdexcept>
#include <string>

#include "socc/channels.hpp"
#include "socc/wall_clock.hpp"

namespace socc::service {
namespace {

constexpr const char* kStartChannel = "SOCC/JOURNAL/START";

void writeEvent(lcm::LogFile& log, const std::string& channel, const void* data, int size,
                const std::filesystem::path& file) {
  lcm::LogEvent event;
  event.eventnum = 0;  // assigned by the log writer
  event.timestamp = nowMicros();
  event.channel = channel;
  event.datalen = size;
  event.data = const_cast<void*>(data);  // LogEvent's API is not const-correct; only read
  if (log.writeEvent(&event) != 0 || std::fflush(log.getFilePtr()) != 0)
    throw std::runtime_error("cannot write journal " + file.string());
}

void syncData(std::FILE* file, const std::filesystem::path& path) {
  if (::fdatasync(::fileno(file)) != 0)
    throw std::runtime_error("cannot fdatasync journal " + path.string() + ": " +
                             std::strerror(errno));
}

// Makes a rename in dir durable (best effort: some file systems refuse fsync on directories).
void syncDirectory(const std::filesystem::path& dir) {
  const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

std::unique_ptr<lcm::LogFile> openLog(const std::filesystem::path& file, const char* mode) {
  auto log = std::make_unique<lcm::LogFile>(file.string(), mode);
  if (!log->good()) throw std::runtime_error("cannot open journal " + file.string());
  return log;
}

}  // namespace

std::optional<JournalSync> parseJournalSync(std::string_view name) {
  for (const auto sync : {JournalSync::kNone, JournalSync::kBatch, JournalSync::kAlways})
    if (name == journalSyncName(sync)) return sync;
  return std::nullopt;
}

const char* journalSyncName(JournalSync sync) {
  switch (sync) {
    case JournalSync::kNone:
      return "none";
    case JournalSync::kBatch:
      return "batch";
    case JournalSync::kAlways:
      return "always";
  }
  return "?";
}

Journal::Journal(std::filesystem::path file, std::int64_t base_sequence, JournalSync sync)
    : file_(std::move(file)), sync_(sync) {
  restart(base_sequence);
}

Journal::~Journal() = default;

void Journal::restart(std::int64_t base_sequence) {
  log_.reset();
  // Write the new journal beside the old one and rename it over: a crash leaves either the
  // old or the new journal, never a half-written start event.
  const std::filesystem::path tmp = file_.string() + ".tmp";
  {
    auto log = openLog(tmp, "w");
    std::uint8_t base[8];
    for (int i = 0; i < 8; ++i) base[i] = static_cast<std::uint8_t>(base_sequence >> (56 - 8 * i));
    writeEvent(*log, kStartChannel, base, sizeof(base), tmp);
    // Always (once per snapshot): after a power loss the name must not point at an empty file.
    syncData(log->getFilePtr(), tmp);
  }
  std::error_code ec;
  std::filesystem::rename(tmp, file_, ec);
  if (ec)
    throw std::runtime_error("cannot replace journal " + file_.string() + ": " + ec.message());
  syncDirectory(file_.parent_path());
  log_ = openLog(file_, "a");
  base_sequence_ = base_sequence;
  entries_ = 0;
  unsynced_ = false;
}

void Journal::append(const std::uint8_t* encoded_request, std::size_t size) {
  writeEvent(*log_, channels::request(channels::kIntegrate), encoded_request,
             static_cast<int>(size), file_);
  ++entries_;
  unsynced_ = true;
  if (sync_ == JournalSync::kAlways) sync();
}

void Journal::sync() {
  if (!unsynced_ || sync_ == JournalSync::kNone) return;
  syncData(log_->getFilePtr(), file_);
  unsynced_ = false;
  ++syncs_;
}

JournalContents Journal::read(const std::filesystem::path& file) {
  if (!std::filesystem::exists(file))
    throw std::runtime_error("journal " + file.string() + " does not exist");
  lcm::LogFile log(file.string(), "r");
  if (!log.good()) throw std::runtime_error("cannot open journal " + file.string());
  const lcm::LogEvent* start = log.readNextEvent();
  if (start == nullptr || start->channel != kStartChannel || start->datalen != 8)
    throw std::runtime_error(file.string() + " is not a socc journal (no start event)");
  JournalContents contents;
  const auto* base = static_cast<const std::uint8_t*>(start->data);
  std::uint64_t value = 0;
  for (int i = 0; i < 8; ++i) value = (value << 8) | base[i];
  contents.base_sequence = static_cast<std::int64_t>(value);

  const std::string integrate_channel = channels::request(channels::kIntegrate);
  while (const lcm::LogEvent* event = log.readNextEvent()) {
    if (event->channel != integrate_channel || event->datalen <= 0) continue;
    const auto* data = static_cast<const std::uint8_t*>(event->data);
    contents.requests.emplace_back(data, data + event->datalen);
  }
  return contents;
}

}  // namespace socc::service
