// Names and JSON of the small value types: ChangeKind, DynamicsClass, FrameStats.
#include <cstdio>
#include <string>

#include "tracegraph/scenegraph/ChangeKind.h"
#include "tracegraph/scenegraph/DynamicsClass.h"
#include "tracegraph/scenegraph/FrameStats.h"

namespace tg {

std::string toString(ChangeKind mask) {
  static constexpr struct {
    ChangeKind kind;
    const char* name;
  } kNames[] = {{ChangeKind::Transform, "Transform"},   {ChangeKind::Points, "Points"},
                {ChangeKind::Topology, "Topology"},     {ChangeKind::Material, "Material"},
                {ChangeKind::Structure, "Structure"},   {ChangeKind::Visibility, "Visibility"},
                {ChangeKind::Connection, "Connection"}, {ChangeKind::Parameter, "Parameter"}};
  std::string s;
  for (const auto& n : kNames) {
    if (!hasAny(mask, n.kind)) continue;
    if (!s.empty()) s += '|';
    s += n.name;
  }
  return s.empty() ? "None" : s;
}

std::string_view dynamicsClassName(DynamicsClass c) {
  switch (c) {
    case DynamicsClass::Static:
      return "static";
    case DynamicsClass::Rigid:
      return "rigid";
    case DynamicsClass::Deforming:
      return "deforming";
  }
  return "unknown";
}

namespace {

std::string number(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

}  // namespace

std::string toJson(const FrameStats& s) {
  std::string j = "{\"frame\":" + std::to_string(s.frame);
  j += ",\"time\":" + number(s.time);
  j += ",\"triangles\":{\"static\":" + std::to_string(s.triangles.statics) +
       ",\"rigid\":" + std::to_string(s.triangles.rigid) +
       ",\"deforming\":" + std::to_string(s.triangles.deforming) + "}";
  j += ",\"instances\":" + std::to_string(s.instances);
  j += ",\"objects_rebuilt\":" + std::to_string(s.objectsRebuilt);
  j += ",\"triangles_rebuilt\":" + std::to_string(s.trianglesRebuilt);
  j += ",\"reclassified\":" + std::to_string(s.reclassified);
  j += ",\"sync_ms\":" + number(s.syncMs);
  j += ",\"rebuild_ms\":" + number(s.rebuildMs);
  j += ",\"toplevel_ms\":" + number(s.toplevelMs);
  j += ",\"render_ms\":" + number(s.renderMs);
  j += ",\"rays\":{\"primary\":" + std::to_string(s.rays.primary) +
       ",\"shadow\":" + std::to_string(s.rays.shadow) +
       ",\"reflection\":" + std::to_string(s.rays.reflection) +
       ",\"refraction\":" + std::to_string(s.rays.refraction) +
       ",\"total\":" + std::to_string(s.rays.total()) + "}";
  // Fields added after the first version go last, so that readers of the original keys are
  // unaffected.
  j += ",\"objects_refitted\":" + std::to_string(s.objectsRefitted) + "}";
  return j;
}

}  // namespace tg
