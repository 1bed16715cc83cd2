#include "scene_graph_tracker/util/progress_bar.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace sgt {

ProgressBar::ProgressBar(std::string label, std::size_t total)
    : label_(std::move(label)),
      total_(total),
      tty_(isatty(STDERR_FILENO) != 0),
      start_(std::chrono::steady_clock::now()) {}

void ProgressBar::update(std::size_t done) {
  const auto now = std::chrono::steady_clock::now();
  if (!tty_ || (now - last_draw_ < std::chrono::milliseconds(100) && done < total_)) return;
  last_draw_ = now;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double frac = total_ ? static_cast<double>(done) / total_ : 1.0;
  const int width = 30, filled = static_cast<int>(frac * width);
  const double left = done ? elapsed / done * (total_ - done) : 0.0;
  std::fprintf(stderr, "\r%s [%.*s%*s] %zu/%zu %5.1f/s  %.0f s left ", label_.c_str(), filled,
               "##############################", width - filled, "", done, total_,
               done / std::max(elapsed, 1e-9), left);
  std::fflush(stderr);
}

void ProgressBar::finish() {
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  if (tty_) std::fputc('\n', stderr);
  std::fprintf(stderr, "%s: %zu done in %.1f s\n", label_.c_str(), total_, elapsed);
}

}  // namespace sgt
