/// @file KeyframeDeformer.h
/// Vertex lists at key times, linearly interpolated (BART's animated triangle patches).
#pragma once

#include "tracegraph/nodes/Deformer.h"
#include "tracegraph/scenegraph/SField.h"

namespace tg::nodes {

/// Holds `times.size()` keyframes of n points (and optionally n normals) one after the other
/// and outputs the linear blend of the two keyframes around the clock time; before the first
/// key the first frame, after the last the last frame, or with `loop` the sequence repeats.
/// This is BART's "tpa" (animated triangle patch) semantics.
class KeyframeDeformer : public Deformer {
 public:
  /// A new deformer without keyframes.
  static ref_ptr<KeyframeDeformer> create() {
    return ref_ptr<KeyframeDeformer>(new KeyframeDeformer());
  }
  std::string_view className() const override { return "KeyframeDeformer"; }
  void evaluate(double time) override;

  MFFloat times{*this, "times", ChangeKind::Parameter};            ///< seconds, non-decreasing
  MFVec3f keyPoints{*this, "keyPoints", ChangeKind::Parameter};    ///< times.size() * n
  MFVec3f keyNormals{*this, "keyNormals", ChangeKind::Parameter};  ///< empty or as keyPoints
  /// Repeat instead of holding the last value.
  SFBool loop{*this, "loop", ChangeKind::Parameter, false};

 protected:
  KeyframeDeformer() = default;
  bool producesNormals() const override { return !keyNormals.empty(); }
};

}  // namespace tg::nodes
