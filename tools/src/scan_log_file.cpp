#include "socc/tools/scan_log_file.hpp"

#include <stdexcept>
#include <system_error>

namespace socc::tools {

ScanLogFile::ScanLogFile(std::filesystem::path path)
    : path_(std::move(path)), log_(std::make_unique<lcm::LogFile>(path_.string(), "w")) {
  if (!log_->good()) throw std::runtime_error(path_.string() + ": cannot open for writing");
}

ScanLogFile::~ScanLogFile() {
  log_.reset();  // closed before a removal
  if (finished_) return;
  std::error_code ignored;
  std::filesystem::remove(path_, ignored);
}

void ScanLogFile::append(const std::string& channel, const scan_t& msg, std::int64_t timestamp,
                         const std::string& what) {
  buf_.resize(static_cast<std::size_t>(msg.getEncodedSize()));
  if (msg.encode(buf_.data(), 0, static_cast<int>(buf_.size())) != static_cast<int>(buf_.size()))
    throw std::runtime_error(what + " does not encode");
  lcm::LogEvent event;
  event.eventnum = events_++;
  event.timestamp = timestamp;
  event.channel = channel;
  event.datalen = static_cast<std::int32_t>(buf_.size());
  event.data = buf_.data();
  if (log_->writeEvent(&event) != 0) throw std::runtime_error(path_.string() + ": write error");
}

void ScanLogFile::finish() {
  finished_ = true;
}

}  // namespace socc::tools
