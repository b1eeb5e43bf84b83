#include "tracegraph/scenegraph/Route.h"

#include <string>

#include "tracegraph/backend/Error.h"
#include "tracegraph/scenegraph/Field.h"

namespace tg {

void route(Node& from, std::string_view fromField, Node& to, std::string_view toField) {
  Field* source = from.field(fromField);
  if (!source)
    throw Error("route: " + from.label() + " has no field '" + std::string(fromField) + "'");
  Field* target = to.field(toField);
  if (!target) throw Error("route: " + to.label() + " has no field '" + std::string(toField) + "'");
  target->connectFrom(*source);
}

}  // namespace tg
