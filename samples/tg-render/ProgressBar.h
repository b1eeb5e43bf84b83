// A one-line progress bar on stderr for multi-frame work.
#pragma once

#include <chrono>
#include <string>

namespace tg::render_tool {

/// Draws "[=====     ] 12/40 frames, 3.1 fps" on stderr, redrawn in place. Silent when
/// stderr is not a terminal or when disabled.
class ProgressBar {
 public:
  ProgressBar(int total, bool enabled);
  ~ProgressBar();
  void update(int done);

 private:
  int total_;
  bool enabled_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace tg::render_tool
