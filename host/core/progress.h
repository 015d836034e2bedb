#pragma once
// A progress bar on stderr for work that may take over a second. It stays silent until the
// work has run for `delay_ms` (so short work prints nothing) and when stderr is not a
// terminal it prints a line per 10 % instead of redrawing.
#include <cstddef>
#include <string>

#include "core/timer.h"

namespace nf {

class Progress {
 public:
  Progress(std::string label, std::size_t total, double delay_ms = 1000.0);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  void advance(std::size_t n = 1);
  void finish();

 private:
  void draw(bool final);
  std::string label_;
  std::size_t total_;
  std::size_t done_ = 0;
  double delay_ms_;
  Timer timer_;
  bool shown_ = false;
  bool finished_ = false;
  bool tty_;
  int last_decile_ = -1;
  double last_draw_ms_ = -1e9;
};

}  // namespace nf
