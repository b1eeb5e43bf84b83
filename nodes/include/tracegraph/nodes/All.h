/// @file All.h
/// Every public header of the concrete nodes (for the umbrella <tracegraph/tracegraph.h>).
///
/// The concrete nodes live in namespace tg::nodes: the renderer's plain structs of the same
/// Inventor names (tg::Material, tg::Texture, tg::Camera, tg::PointLight, ...) are in tg, and a
/// sample that loads a graph and renders it includes both.
#pragma once

#include "tracegraph/nodes/Camera.h"
#include "tracegraph/nodes/CoordinateInterpolator.h"
#include "tracegraph/nodes/Deformer.h"
#include "tracegraph/nodes/DirectionalLight.h"
#include "tracegraph/nodes/KeyInterval.h"
#include "tracegraph/nodes/KeyframeDeformer.h"
#include "tracegraph/nodes/Material.h"
#include "tracegraph/nodes/MatrixTransform.h"
#include "tracegraph/nodes/Mesh.h"
#include "tracegraph/nodes/MorphDeformer.h"
#include "tracegraph/nodes/OrientationInterpolator.h"
#include "tracegraph/nodes/PointLight.h"
#include "tracegraph/nodes/PositionInterpolator.h"
#include "tracegraph/nodes/ScalarInterpolator.h"
#include "tracegraph/nodes/Separator.h"
#include "tracegraph/nodes/SkinDeformer.h"
#include "tracegraph/nodes/SpotLight.h"
#include "tracegraph/nodes/Switch.h"
#include "tracegraph/nodes/Texture.h"
#include "tracegraph/nodes/TimeSensor.h"
#include "tracegraph/nodes/Transform.h"
