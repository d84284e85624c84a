#include <future>
#include <string>
#include <utility>

#include "socc/odom/scan_source.hpp"

namespace socc::odom {
namespace {

// Reads the next scan in a worker thread while the caller works on the current one.
class ReadAheadScanSource : public ScanSource {
 public:
  explicit ReadAheadScanSource(std::unique_ptr<ScanSource> source)
      : source_(std::move(source)),
        remaining_(source_->remaining()),
        timing_(source_->timing()),
        live_(source_->live()) {
    readNext();
  }
  ~ReadAheadScanSource() override {
    if (pending_.valid()) pending_.wait();  // the worker uses source_
  }

  std::optional<Scan> next() override {
    std::optional<Scan> scan = pending_.get();  // rethrows the reader's error
    if (!scan) return scan;
    if (remaining_ > 0) --remaining_;
    readNext();
    return scan;
  }
  std::size_t remaining() const override { return remaining_; }
  std::string timing() const override { return timing_; }
  bool live() const override { return live_; }

 private:
  void readNext() {
    pending_ = std::async(std::launch::async, [this] { return source_->next(); });
  }

  std::unique_ptr<ScanSource> source_;
  std::size_t remaining_;  // source_'s count is the worker's to change
  std::string timing_;
  bool live_;
  std::future<std::optional<Scan>> pending_;
};

}  // namespace

std::unique_ptr<ScanSource> readAhead(std::unique_ptr<ScanSource> source) {
  return std::make_unique<ReadAheadScanSource>(std::move(source));
}

}  // namespace socc::odom
