/// @file ref_ptr.h
/// Owning smart pointer for intrusively counted objects (nodes, animators).
#pragma once

#include <cstddef>
#include <functional>
#include <utility>

namespace tg {

/// Shares ownership of a Referenced object; copying adds a reference, destruction drops one.
template <typename T>
class ref_ptr {
 public:
  /// Empty pointer.
  ref_ptr() noexcept = default;
  /// Empty pointer.
  ref_ptr(std::nullptr_t) noexcept {}  // NOLINT(google-explicit-constructor)
  /// Takes a reference to `p` (which may already be owned elsewhere).
  explicit ref_ptr(T* p) noexcept : p_(p) {
    if (p_) p_->ref();
  }
  /// Copy adds a reference.
  ref_ptr(const ref_ptr& o) noexcept : ref_ptr(o.p_) {}
  /// Move transfers the reference.
  ref_ptr(ref_ptr&& o) noexcept : p_(std::exchange(o.p_, nullptr)) {}
  /// Converting copy from a pointer to a derived class.
  template <typename U>
  ref_ptr(const ref_ptr<U>& o) noexcept : ref_ptr(o.get()) {}  // NOLINT
  /// Converting move from a pointer to a derived class.
  template <typename U>
  ref_ptr(ref_ptr<U>&& o) noexcept : p_(o.release()) {}  // NOLINT
  ~ref_ptr() {
    if (p_) p_->unref();
  }

  /// Copy assignment (self-safe).
  ref_ptr& operator=(const ref_ptr& o) noexcept {
    ref_ptr(o).swap(*this);
    return *this;
  }
  /// Move assignment.
  ref_ptr& operator=(ref_ptr&& o) noexcept {
    ref_ptr(std::move(o)).swap(*this);
    return *this;
  }

  /// The object, or null.
  T* get() const noexcept { return p_; }
  /// The object (must not be empty).
  T& operator*() const noexcept { return *p_; }
  /// Member access (must not be empty).
  T* operator->() const noexcept { return p_; }
  /// True when not empty.
  explicit operator bool() const noexcept { return p_ != nullptr; }
  /// Gives up ownership without dropping the reference (the caller now holds it).
  T* release() noexcept { return std::exchange(p_, nullptr); }
  /// Exchanges the pointers without touching the counts.
  void swap(ref_ptr& o) noexcept { std::swap(p_, o.p_); }

  /// Casts to a derived type; empty when the object is not a U.
  template <typename U>
  ref_ptr<U> cast() const {
    return ref_ptr<U>(dynamic_cast<U*>(p_));
  }

  /// Same object (or both empty).
  friend bool operator==(const ref_ptr& a, const ref_ptr& b) noexcept { return a.p_ == b.p_; }
  /// True when empty.
  friend bool operator==(const ref_ptr& a, std::nullptr_t) noexcept { return a.p_ == nullptr; }
  /// True when holding b.
  friend bool operator==(const ref_ptr& a, const T* b) noexcept { return a.p_ == b; }

 private:
  T* p_ = nullptr;
};

}  // namespace tg

// Doxygen cannot place a std:: specialisation declared outside namespace std ("internal
// inconsistency"), so it is left out of the reference.
/// @cond
/// Hash by address so ref_ptr can key unordered containers.
template <typename T>
struct std::hash<tg::ref_ptr<T>> {
  std::size_t operator()(const tg::ref_ptr<T>& p) const noexcept {
    return std::hash<T*>()(p.get());
  }
};
/// @endcond
