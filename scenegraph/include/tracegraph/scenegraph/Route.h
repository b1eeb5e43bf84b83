/// @file Route.h
/// VRML-style ROUTE by node and field names, for loaders.
#pragma once

#include <string_view>

#include "tracegraph/scenegraph/Node.h"

namespace tg {

/// ROUTE from.fromField TO to.toField: connects `to`'s field from `from`'s field
/// (Field::connectFrom). Throws tg::Error naming "route" and the missing field or the
/// connection problem; nothing changes then.
void route(Node& from, std::string_view fromField, Node& to, std::string_view toField);

}  // namespace tg
