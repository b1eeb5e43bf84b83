/// @file tracegraph.h
/// Every public header of Tracegraph: link Tracegraph::tracegraph and include this one file.
///
/// The layers, bottom up (each only uses the ones before it):
/// - backend: math, meshes, object kd-trees, the Algorithm 1 top level, two-level traversal,
///   the C++ tg::Scene API, the OpenRT-style API (tg::rtBeginObject ...) and the renderer;
/// - scenegraph: nodes, fields, change notification, the dynamics classifier and tg::SceneGraph,
///   which keeps a backend scene equal to the graph, plus tg::SceneRenderer;
/// - nodes: the concrete nodes in namespace tg::nodes (Separator, Transform, Mesh, deformers,
///   Material, lights, Camera, interpolators);
/// - loaders: BART AFF/NFF, X3D and Assimp files, and the built-in demo scene.
///
/// Projects that need one layer only can include its headers directly and link the layer's
/// target (Tracegraph::backend, Tracegraph::scenegraph, Tracegraph::nodes, Tracegraph::loaders).
#pragma once

// backend
#include "tracegraph/backend/Affine.h"
#include "tracegraph/backend/Box3.h"
#include "tracegraph/backend/DynamicsClass.h"
#include "tracegraph/backend/Error.h"
#include "tracegraph/backend/KdTree.h"
#include "tracegraph/backend/KdTreeAccel.h"
#include "tracegraph/backend/ObjectAccel.h"
#include "tracegraph/backend/OpenRT.h"
#include "tracegraph/backend/Ray.h"
#include "tracegraph/backend/ReferenceIntersector.h"
#include "tracegraph/backend/Scene.h"
#include "tracegraph/backend/Simd.h"
#include "tracegraph/backend/TopLevelAccel.h"
#include "tracegraph/backend/TopLevelKdTree.h"
#include "tracegraph/backend/TriangleMesh.h"
#include "tracegraph/backend/Vec3.h"
#include "tracegraph/backend/WatertightTriangle.h"
#include "tracegraph/backend/render/Camera.h"
#include "tracegraph/backend/render/Image.h"
#include "tracegraph/backend/render/ImageIO.h"
#include "tracegraph/backend/render/Light.h"
#include "tracegraph/backend/render/Material.h"
#include "tracegraph/backend/render/Optics.h"
#include "tracegraph/backend/render/RayOffset.h"
#include "tracegraph/backend/render/RenderScene.h"
#include "tracegraph/backend/render/RenderStats.h"
#include "tracegraph/backend/render/Renderer.h"
#include "tracegraph/backend/render/Texture.h"

// scenegraph
#include "tracegraph/scenegraph/All.h"
#include "tracegraph/scenegraph/SceneRenderer.h"

// nodes
#include "tracegraph/nodes/All.h"

// loaders
#include "tracegraph/loaders/AffDocument.h"
#include "tracegraph/loaders/AffLoader.h"
#include "tracegraph/loaders/AffParser.h"
#include "tracegraph/loaders/AssimpLoader.h"
#include "tracegraph/loaders/DemoScene.h"
#include "tracegraph/loaders/KochanekBartels.h"
#include "tracegraph/loaders/LoadedScene.h"
#include "tracegraph/loaders/SceneSource.h"
#include "tracegraph/loaders/X3dLoader.h"
