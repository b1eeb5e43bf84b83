/// @file SField.h
/// Single-valued fields (SFVec3f, SFRotation, ...).
#pragma once

#include <string>

#include "tracegraph/backend/Error.h"
#include "tracegraph/scenegraph/Field.h"
#include "tracegraph/scenegraph/FieldTraits.h"

namespace tg {

/// A field holding one value of type T. Setting an equal value does nothing (no notification),
/// so an animator at rest leaves its targets clean.
template <typename T>
class SField final : public Field {
 public:
  /// The value type.
  using value_type = T;

  /// Declares the field inside `owner` (call from the owner's member initialisers).
  SField(Node& owner, const char* name, ChangeKind kind, T initial = T{})
      : Field(owner, name, kind), value_(std::move(initial)) {}

  /// The current value.
  const T& getValue() const { return value_; }
  /// The current value.
  const T& value() const { return value_; }
  /// Sets the value and notifies when it differs. Throws tg::Error for NaN/Inf values or while
  /// the owner's graph renders; the value is then unchanged.
  void setValue(const T& v) {
    beginEdit("setValue");
    if (!FieldTraits<T>::finite(v))
      throw Error(std::string(typeName()) + " " + std::string(name()) +
                  "::setValue: value is NaN or infinite");
    if (v == value_) return;
    value_ = v;
    valueChanged();
  }
  /// Same as setValue.
  SField& operator=(const T& v) {
    setValue(v);
    return *this;
  }
  std::string_view typeName() const override { return FieldTraits<T>::single; }
  void copyValueFrom(const Field& source) override {
    setValue(static_cast<const SField&>(source).value_);
  }

 private:
  T value_;
};

/// SFBool: one boolean.
using SFBool = SField<bool>;
/// SFInt32: one 32-bit integer.
using SFInt32 = SField<std::int32_t>;
/// SFFloat: one float.
using SFFloat = SField<float>;
/// SFTime: seconds in double.
using SFTime = SField<double>;
/// SFString: one string (file names).
using SFString = SField<std::string>;
/// SFVec2f: one 2D vector.
using SFVec2f = SField<Vec2f>;
/// SFVec3f: one 3D vector.
using SFVec3f = SField<Vec3f>;
/// SFColor: one RGB colour.
using SFColor = SField<Color>;
/// SFRotation: axis + angle (radians).
using SFRotation = SField<Rotation>;
/// SFMatrix: one affine matrix in double.
using SFMatrix = SField<Affine3d>;

}  // namespace tg
