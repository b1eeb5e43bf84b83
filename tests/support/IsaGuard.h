// Restores the SIMD kernel set when a test that switches kernels ends, however it ends.
#pragma once

#include "tracegraph/backend/Simd.h"

namespace tg::test {

/// Saves the active kernel set (activeSimdIsa) and makes it active again on destruction.
struct IsaGuard {
  SimdIsa saved = activeSimdIsa();
  IsaGuard() = default;
  IsaGuard(const IsaGuard&) = delete;
  IsaGuard& operator=(const IsaGuard&) = delete;
  ~IsaGuard() { setSimdIsa(saved); }
};

}  // namespace tg::test
