/// @file DemoScene.h
/// The built-in demo scene: shows the three dynamics classes at work without any file.
#pragma once

#include "tracegraph/scenegraph/Node.h"
#include "tracegraph/scenegraph/SceneRenderer.h"
#include "tracegraph/scenegraph/ref_ptr.h"

namespace tg {

/// What makeDemoScene() builds, with the counts its test asserts.
struct DemoScene {
  /// Root of the scene, for SceneGraph::setRoot.
  ref_ptr<Node> root;
  /// Background and ambient light.
  SceneLook look;
  double duration = 8.0;  ///< seconds of animation; the loop repeats after it
  ///@{
  /// Triangles the classifier should put in each class (static room, mirror, glass and
  /// pedestal; the two-part robot arm; the wave).
  std::size_t staticTriangles = 0, rigidTriangles = 0, deformingTriangles = 0;
  ///@}
};

/// Builds the demo: a static room with a mirror and a glass sphere, a robot arm whose shoulder
/// and elbow turn on a chain of animated transforms (with a static offset below the elbow that
/// the classifier bakes into the object), a deforming wave surface, two point lights and a
/// camera that swings around the room, all driven by one looping TimeSensor.
DemoScene makeDemoScene();

}  // namespace tg
