#include "socc/progress_bar.hpp"

#include <unistd.h>

#include <cstdio>

namespace socc {

ProgressBar::ProgressBar(std::string label, std::size_t total, bool enabled)
    : label_(std::move(label)),
      total_(total),
      enabled_(enabled),
      tty_(isatty(STDERR_FILENO) != 0),
      start_(std::chrono::steady_clock::now()) {}

ProgressBar::~ProgressBar() { finish(); }

void ProgressBar::tick(const std::string& extra) {
  ++done_;
  if (enabled_) draw(extra);
}

void ProgressBar::finish() {
  if (finished_) return;
  finished_ = true;
  if (enabled_ && tty_ && done_ > 0) std::fputc('\n', stderr);
}

void ProgressBar::draw(const std::string& extra) {
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double hz = elapsed > 0 ? static_cast<double>(done_) / elapsed : 0.0;
  const double frac = total_ ? static_cast<double>(done_) / static_cast<double>(total_) : 1.0;
  const double eta = hz > 0 && total_ > done_ ? static_cast<double>(total_ - done_) / hz : 0.0;
  if (!tty_) {
    const int decile = static_cast<int>(frac * 10.0);
    if (decile == last_decile_ && done_ != total_) return;
    last_decile_ = decile;
    std::fprintf(stderr, "%s: %zu/%zu (%.1f Hz) %s\n", label_.c_str(), done_, total_, hz,
                 extra.c_str());
    return;
  }
  constexpr int kWidth = 30;
  const int filled = static_cast<int>(frac * kWidth);
  std::string bar(static_cast<std::size_t>(filled), '#');
  bar.resize(kWidth, '.');
  std::fprintf(stderr, "\r%s [%s] %zu/%zu %5.1f Hz ETA %4.0fs %s\033[K", label_.c_str(),
               bar.c_str(), done_, total_, hz, eta, extra.c_str());
  std::fflush(stderr);
}

}  // namespace socc
