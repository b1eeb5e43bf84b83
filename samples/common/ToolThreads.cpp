#include "ToolThreads.h"

#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <cstddef>

namespace tg::tools {

int runWithThreads(int threads, const std::function<int()>& body) {
  const int n = threads > 0 ? threads : tbb::this_task_arena::max_concurrency();
  // Caps every arena, including those that library code creates on its own.
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                                  static_cast<std::size_t>(n));
  tbb::task_arena arena(n);
  int code = 0;
  arena.execute([&] { code = body(); });
  return code;
}

}  // namespace tg::tools
