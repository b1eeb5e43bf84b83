#include "ProgressBar.h"

#include <unistd.h>

#include <cstdio>

namespace tg::render_tool {

ProgressBar::ProgressBar(int total, bool enabled)
    : total_(total),
      enabled_(enabled && total > 1 && isatty(STDERR_FILENO) == 1),
      start_(std::chrono::steady_clock::now()) {}

ProgressBar::~ProgressBar() {
  if (enabled_) std::fputs("\n", stderr);
}

void ProgressBar::update(int done) {
  if (!enabled_) return;
  constexpr int kWidth = 30;
  const int filled = total_ > 0 ? done * kWidth / total_ : kWidth;
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  char bar[kWidth + 1];
  for (int i = 0; i < kWidth; ++i) bar[i] = i < filled ? '=' : ' ';
  bar[kWidth] = '\0';
  std::fprintf(stderr, "\r[%s] %d/%d frames, %.2f fps", bar, done, total_,
               seconds > 0.0 ? done / seconds : 0.0);
  std::fflush(stderr);
}

}  // namespace tg::render_tool
