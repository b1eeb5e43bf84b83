/// @file DynamicsClass.h
/// Names of the three dynamics classes (the enum itself is the backend's, shared with the
/// renderer's `classes` mode).
#pragma once

#include <string_view>

#include "tracegraph/backend/DynamicsClass.h"

namespace tg {

/// "static", "rigid" or "deforming".
std::string_view dynamicsClassName(DynamicsClass c);

}  // namespace tg
