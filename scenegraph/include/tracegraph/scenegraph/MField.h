/// @file MField.h
/// Multiple-valued fields (MFVec3f points, MFInt32 indices, ...).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "tracegraph/backend/Error.h"
#include "tracegraph/scenegraph/Field.h"
#include "tracegraph/scenegraph/FieldTraits.h"

namespace tg {

/// A field holding an array of T. Every setter validates (no NaN/Inf) before changing
/// anything and notifies once per call.
template <typename T>
class MField final : public Field {
 public:
  /// The element type.
  using value_type = T;

  /// Declares the field inside `owner` (call from the owner's member initialisers).
  MField(Node& owner, const char* name, ChangeKind kind, std::vector<T> initial = {})
      : Field(owner, name, kind), values_(std::move(initial)) {}

  /// The values.
  const std::vector<T>& getValues() const { return values_; }
  /// The values.
  const std::vector<T>& values() const { return values_; }
  /// Number of values.
  std::size_t size() const { return values_.size(); }
  /// True when there are no values.
  bool empty() const { return values_.empty(); }
  /// Value `i` (unchecked).
  const T& operator[](std::size_t i) const { return values_[i]; }

  /// Replaces all values; notifies when they differ.
  void setValues(std::vector<T> v) {
    beginEdit("setValues");
    check(v, "setValues");
    if (v == values_) return;
    values_ = std::move(v);
    valueChanged();
  }
  /// Same as setValues.
  MField& operator=(std::vector<T> v) {
    setValues(std::move(v));
    return *this;
  }
  /// Sets value `i`, growing the array with default values when `i` is past the end.
  void set1Value(std::size_t i, const T& v) {
    beginEdit("set1Value");
    if (!FieldTraits<T>::finite(v))
      throw Error(std::string(typeName()) + " " + std::string(name()) +
                  "::set1Value: value is NaN or infinite");
    if (i < values_.size() && values_[i] == v) return;
    if (i >= values_.size()) values_.resize(i + 1);
    values_[i] = v;
    valueChanged();
  }
  /// Edits the array in place through `edit(std::vector<T>&)` and notifies once; when the
  /// result holds NaN/Inf values the previous array is restored and tg::Error is thrown.
  template <typename F>
  void edit(F&& edit) {
    beginEdit("edit");
    std::vector<T> copy = values_;
    std::forward<F>(edit)(copy);
    check(copy, "edit");
    values_ = std::move(copy);
    valueChanged();
  }
  std::string_view typeName() const override { return FieldTraits<T>::multi; }
  void copyValueFrom(const Field& source) override {
    setValues(static_cast<const MField&>(source).values_);
  }

 private:
  void check(const std::vector<T>& v, const char* call) const {
    for (std::size_t i = 0; i < v.size(); ++i)
      if (!FieldTraits<T>::finite(v[i]))
        throw Error(std::string(typeName()) + " " + std::string(name()) + "::" + call + ": value " +
                    std::to_string(i) + " is NaN or infinite");
  }

  std::vector<T> values_;
};

/// MFInt32: array of 32-bit integers (indices).
using MFInt32 = MField<std::int32_t>;
/// MFFloat: array of floats (keys, weights).
using MFFloat = MField<float>;
/// MFTime: array of times in seconds.
using MFTime = MField<double>;
/// MFString: array of strings.
using MFString = MField<std::string>;
/// MFVec2f: array of 2D vectors (texture coordinates).
using MFVec2f = MField<Vec2f>;
/// MFVec3f: array of 3D vectors (points, normals).
using MFVec3f = MField<Vec3f>;
/// MFColor: array of colours.
using MFColor = MField<Color>;
/// MFRotation: array of rotations (orientation keys).
using MFRotation = MField<Rotation>;
/// MFMatrix: array of affine matrices (inverse bind matrices).
using MFMatrix = MField<Affine3d>;

}  // namespace tg
