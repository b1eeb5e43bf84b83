/// @file ToolThreads.h
/// The worker threads of a command-line tool.
#pragma once

#include <functional>

namespace tg::tools {

/// Runs `body` on the calling thread inside a task arena of `threads` workers (every core when
/// 0), with oneTBB's parallelism capped at that number for the whole process, and returns what
/// `body` returns. The calling thread matters to tg-view: GLFW must run on the main thread.
int runWithThreads(int threads, const std::function<int()>& body);

}  // namespace tg::tools
