#include "socc/odom/scan_preparer.hpp"

#include <stdexcept>
#include <utility>

namespace socc::odom {

ScanPreparer::ScanPreparer(ScanSource& source, const OdomConfig& config,
                           std::int64_t skip_until_seq)
    : source_(source), config_(config), skip_until_seq_(skip_until_seq) {
  pending_ = std::async(std::launch::async, [this] { return readAndPrepare(); });
}

ScanPreparer::~ScanPreparer() {
  if (pending_.valid()) pending_.wait();
}

std::optional<PreparedInput> ScanPreparer::next() {
  std::optional<PreparedInput> input = pending_.get();  // rethrows the source's error
  if (input) pending_ = std::async(std::launch::async, [this] { return readAndPrepare(); });
  return input;
}

std::optional<PreparedInput> ScanPreparer::readAndPrepare() const {
  std::optional<Scan> scan = source_.next();
  if (!scan) return std::nullopt;
  PreparedInput out;
  out.seq = scan->seq;
  out.name = std::move(scan->name);
  out.skipped = scan->seq <= skip_until_seq_;
  if (out.skipped) return out;
  try {
    out.scan = prepareScan(config_, scan->cloud, scan->seq, scan->utime);
    if (config_.use_gravity) out.scan->gravity = scan->gravity;
  } catch (const std::invalid_argument& e) {
    out.problem = e.what();
  }
  return out;
}

}  // namespace socc::odom
