/// @file FieldTraits.h
/// Per value type: the Inventor/VRML field names and the finiteness check applied on set.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>

#include "tracegraph/backend/Affine.h"
#include "tracegraph/backend/TriangleMesh.h"
#include "tracegraph/backend/Vec3.h"
#include "tracegraph/scenegraph/Color.h"
#include "tracegraph/scenegraph/Rotation.h"

namespace tg {

/// Names and validity of the values a field may hold; specialised for each field value type.
template <typename T>
struct FieldTraits;

/// SFBool / MFBool.
template <>
struct FieldTraits<bool> {
  ///@{
  /// Inventor/VRML names of the single- and multi-valued field types.
  static constexpr std::string_view single = "SFBool", multi = "MFBool";
  ///@}
  /// Always true.
  static bool finite(bool) { return true; }
};
/// SFInt32 / MFInt32.
template <>
struct FieldTraits<std::int32_t> {
  ///@{
  /// Inventor/VRML names of the single- and multi-valued field types.
  static constexpr std::string_view single = "SFInt32", multi = "MFInt32";
  ///@}
  /// Always true.
  static bool finite(std::int32_t) { return true; }
};
/// SFFloat / MFFloat.
template <>
struct FieldTraits<float> {
  ///@{
  /// Inventor/VRML names of the single- and multi-valued field types.
  static constexpr std::string_view single = "SFFloat", multi = "MFFloat";
  ///@}
  /// True when v is neither NaN nor infinite.
  static bool finite(float v) { return std::isfinite(v); }
};
/// SFTime / MFTime (seconds, double).
template <>
struct FieldTraits<double> {
  ///@{
  /// Inventor/VRML names of the single- and multi-valued field types.
  static constexpr std::string_view single = "SFTime", multi = "MFTime";
  ///@}
  /// True when v is neither NaN nor infinite.
  static bool finite(double v) { return std::isfinite(v); }
};
/// SFString / MFString.
template <>
struct FieldTraits<std::string> {
  ///@{
  /// Inventor/VRML names of the single- and multi-valued field types.
  static constexpr std::string_view single = "SFString", multi = "MFString";
  ///@}
  /// Always true.
  static bool finite(const std::string&) { return true; }
};
/// SFVec2f / MFVec2f.
template <>
struct FieldTraits<Vec2f> {
  ///@{
  /// Inventor/VRML names of the single- and multi-valued field types.
  static constexpr std::string_view single = "SFVec2f", multi = "MFVec2f";
  ///@}
  /// True when both coordinates are finite.
  static bool finite(const Vec2f& v) { return std::isfinite(v.u) && std::isfinite(v.v); }
};
/// SFVec3f / MFVec3f.
template <>
struct FieldTraits<Vec3f> {
  ///@{
  /// Inventor/VRML names of the single- and multi-valued field types.
  static constexpr std::string_view single = "SFVec3f", multi = "MFVec3f";
  ///@}
  /// True when every component is finite.
  static bool finite(const Vec3f& v) { return isFinite(v); }
};
/// SFColor / MFColor.
template <>
struct FieldTraits<Color> {
  ///@{
  /// Inventor/VRML names of the single- and multi-valued field types.
  static constexpr std::string_view single = "SFColor", multi = "MFColor";
  ///@}
  /// True when every channel is finite.
  static bool finite(const Color& c) {
    return std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b);
  }
};
/// SFRotation / MFRotation.
template <>
struct FieldTraits<Rotation> {
  ///@{
  /// Inventor/VRML names of the single- and multi-valued field types.
  static constexpr std::string_view single = "SFRotation", multi = "MFRotation";
  ///@}
  /// True when axis and angle are finite.
  static bool finite(const Rotation& r) { return isFinite(r.axis) && std::isfinite(r.angle); }
};
/// SFMatrix / MFMatrix (affine, double).
template <>
struct FieldTraits<Affine3d> {
  ///@{
  /// Inventor/VRML names of the single- and multi-valued field types.
  static constexpr std::string_view single = "SFMatrix", multi = "MFMatrix";
  ///@}
  /// True when every entry is finite.
  static bool finite(const Affine3d& m) { return m.isFinite(); }
};

}  // namespace tg
