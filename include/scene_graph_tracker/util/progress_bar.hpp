// A text progress bar for long offline work (simulation, evaluation): redraws one line on stderr
// with done/total, rate and time left; prints nothing when stderr is not a terminal except a
// final summary line.
#pragma once

#include <chrono>
#include <cstddef>
#include <string>

namespace sgt {

class ProgressBar {
 public:
  ProgressBar(std::string label, std::size_t total);
  void update(std::size_t done);
  void finish();

 private:
  std::string label_;
  std::size_t total_;
  bool tty_;
  std::chrono::steady_clock::time_point start_, last_draw_;
};

}  // namespace sgt
