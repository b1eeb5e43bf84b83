// Large acceleration arrays on transparent huge pages.
//
// A traversal reads a BVH's nodes and its leaf triangles all over their few megabytes. On 4 KiB
// pages that is about two thousand pages for the BART kitchen, wherever the system put them, and
// the trace speed of one and the same tree changed from process to process: 5.4 to 6.7 ms for
// the kitchen's primary rays on two threads, while Embree's stayed within 5.5-5.9 ms. With the
// nodes and the triangles on 2 MiB pages, which Linux gives to memory that asks for them
// (MADV_HUGEPAGE; transparent huge pages are "madvise" by default on Debian), ten of eleven runs
// took 5.4-5.8 ms. Where the system has no huge pages the advice is ignored.
// Internal header: not installed.
#pragma once

#include <cstddef>
#include <cstdlib>
#include <limits>
#include <new>
#include <utility>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace tg::detail {

/// Arrays from this size on are placed on their own 2 MiB-aligned huge pages.
inline constexpr std::size_t kHugePageBytes = std::size_t(2) << 20;

/// The bytes allocateLarge(bytes, ...) takes from the system: whole huge pages from
/// kHugePageBytes on (the kernel backs a touched huge page whole), for memory statistics.
inline constexpr std::size_t largeAllocationBytes(std::size_t bytes) {
  return bytes < kHugePageBytes ? bytes : (bytes + kHugePageBytes - 1) & ~(kHugePageBytes - 1);
}

/// Memory for `bytes` bytes aligned to `alignment`: from operator new below kHugePageBytes;
/// from there on rounded up to whole huge pages, aligned to one and advised to use them (the
/// rounding costs less than one page per array, and only arrays of at least one page).
inline void* allocateLarge(std::size_t bytes, std::size_t alignment) {
  if (bytes < kHugePageBytes) return ::operator new(bytes, std::align_val_t(alignment));
  const std::size_t rounded = largeAllocationBytes(bytes);
  void* p = std::aligned_alloc(kHugePageBytes, rounded);
  if (p == nullptr) throw std::bad_alloc();
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  // Only a hint: it fails harmlessly where transparent huge pages are off.
  (void)::madvise(p, rounded, MADV_HUGEPAGE);
#endif
  return p;
}

/// Frees what allocateLarge(bytes, alignment) returned.
inline void freeLarge(void* p, std::size_t bytes, std::size_t alignment) noexcept {
  if (bytes < kHugePageBytes) {
    ::operator delete(p, std::align_val_t(alignment));
  } else {
    std::free(p);
  }
}

/// The allocator of large acceleration arrays (allocateLarge). Its value-less construct
/// default-initialises, so that growing an array that is about to be overwritten costs no pass
/// over memory (the per-frame top-level rebuilds grow their node arrays so).
template <class T>
struct HugePageAllocator {
  using value_type = T;
  HugePageAllocator() = default;
  template <class U>
  explicit HugePageAllocator(const HugePageAllocator<U>&) noexcept {}

  T* allocate(std::size_t n) {
    if (n > std::numeric_limits<std::size_t>::max() / sizeof(T)) throw std::bad_array_new_length();
    return static_cast<T*>(allocateLarge(n * sizeof(T), alignof(T)));
  }
  void deallocate(T* p, std::size_t n) noexcept { freeLarge(p, n * sizeof(T), alignof(T)); }

  template <class U>
  void construct(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }

  friend bool operator==(const HugePageAllocator&, const HugePageAllocator&) { return true; }
};

}  // namespace tg::detail
