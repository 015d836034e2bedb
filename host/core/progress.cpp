#include "core/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

#include "core/log.h"

namespace nf {

Progress::Progress(std::string label, std::size_t total, double delay_ms)
    : label_(std::move(label)), total_(std::max<std::size_t>(total, 1)), delay_ms_(delay_ms),
      tty_(isatty(STDERR_FILENO) != 0) {}

Progress::~Progress() { finish(); }

void Progress::advance(std::size_t n) {
  done_ = std::min(done_ + n, total_);
  draw(false);
}

void Progress::finish() {
  if (finished_) return;
  finished_ = true;
  if (shown_) draw(true);
}

void Progress::draw(bool final) {
  if (log::level() == log::Level::quiet) return;
  const double now = timer_.ms();
  if (!final && now < delay_ms_) return;
  const double frac = static_cast<double>(done_) / static_cast<double>(total_);
  if (tty_) {
    if (!final && now - last_draw_ms_ < 100.0) return;
    last_draw_ms_ = now;
    const int width = 30;
    const int filled = static_cast<int>(frac * width);
    std::string bar(static_cast<std::size_t>(filled), '#');
    bar.resize(width, '.');
    const double eta = frac > 0 ? now * (1.0 - frac) / frac / 1000.0 : 0.0;
    std::fprintf(stderr, "\r%s [%s] %5.1f%% %.1fs%s", label_.c_str(), bar.c_str(), frac * 100.0, final ? now / 1000.0 : eta,
                 final ? " total\n" : " left ");
  } else {
    const int decile = static_cast<int>(frac * 10.0);
    if (decile == last_decile_) return;  // also: finish() after the 100 % line was printed
    last_decile_ = decile;
    std::fprintf(stderr, "%s: %3.0f%% (%.1fs)\n", label_.c_str(), frac * 100.0, now / 1000.0);
  }
  std::fflush(stderr);
  shown_ = true;
}

}  // namespace nf
