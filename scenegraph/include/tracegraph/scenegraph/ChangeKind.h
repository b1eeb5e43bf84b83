/// @file ChangeKind.h
/// What a change notification says changed; the sync chooses its work from these bits.
#pragma once

#include <cstdint>
#include <string>

namespace tg {

/// Kinds of change carried by notifications, as bits so that several can be merged.
///
/// The sync reads them to pick the cheapest correct update: a Transform change of a dynamic
/// transform only moves instances, a Points change of a deforming mesh only rebuilds its
/// object, a Material change needs no backend work at all, while Structure and Visibility
/// changes re-traverse the enclosing Separator.
enum class ChangeKind : std::uint16_t {
  None = 0,
  Transform = 1u << 0,   ///< a transform's matrix (translation, rotation, matrix, ...)
  Points = 1u << 1,      ///< vertex positions (and the normals that move with them)
  Topology = 1u << 2,    ///< indices, texture coordinates or vertex count of a mesh
  Material = 1u << 3,    ///< appearance only: material, texture; no geometric effect
  Structure = 1u << 4,   ///< children added, removed or replaced
  Visibility = 1u << 5,  ///< which children are traversed (Switch::whichChild)
  Connection = 1u << 6,  ///< a field was connected to or disconnected from an animator
  Parameter = 1u << 7,   ///< lights, camera, animator inputs: no effect on geometry
};

/// Union of change bits.
constexpr ChangeKind operator|(ChangeKind a, ChangeKind b) {
  return static_cast<ChangeKind>(static_cast<std::uint16_t>(a) | static_cast<std::uint16_t>(b));
}
/// Intersection of change bits.
constexpr ChangeKind operator&(ChangeKind a, ChangeKind b) {
  return static_cast<ChangeKind>(static_cast<std::uint16_t>(a) & static_cast<std::uint16_t>(b));
}
/// Adds bits in place.
constexpr ChangeKind& operator|=(ChangeKind& a, ChangeKind b) {
  return a = a | b;
}
/// True when `mask` has any of the bits of `kinds`.
constexpr bool hasAny(ChangeKind mask, ChangeKind kinds) {
  return (mask & kinds) != ChangeKind::None;
}

/// Readable list of the bits, e.g. "Transform|Points" ("None" for no bits).
std::string toString(ChangeKind mask);

}  // namespace tg
