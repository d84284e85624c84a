#pragma once
// A terminal progress bar with rate (Hz) and ETA, for long runs. Writes to stderr;
// prints a plain line every 10 % instead of redrawing when stderr is not a terminal.
#include <chrono>
#include <cstddef>
#include <string>

namespace socc {

class ProgressBar {
 public:
  ProgressBar(std::string label, std::size_t total, bool enabled = true);
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  /// Marks one more item done; extra text (e.g. "12.3 ms") is shown at the end of the line.
  void tick(const std::string& extra = {});
  void finish();

 private:
  void draw(const std::string& extra);

  std::string label_;
  std::size_t total_;
  std::size_t done_ = 0;
  bool enabled_;
  bool tty_;
  bool finished_ = false;
  int last_decile_ = -1;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace socc
