// TimeSensors, interpolators and ROUTEs: X3D field names are mapped onto the nodes' fields
// (set_x / x_changed accepted for x) and connected; ROUTEs into Coordinate and Normal nodes go
// through a MeshDeformer per mesh built from them.
#include <algorithm>

#include "X3dReader.h"
#include "tracegraph/backend/Error.h"
#include "tracegraph/nodes/CoordinateInterpolator.h"
#include "tracegraph/nodes/OrientationInterpolator.h"
#include "tracegraph/nodes/PositionInterpolator.h"
#include "tracegraph/nodes/ScalarInterpolator.h"
#include "tracegraph/scenegraph/Field.h"

namespace tg::x3d {
namespace {

/// X3D field names whose node field is called differently.
std::string_view alias(std::string_view x3d) {
  if (x3d == "transparency") return "transmittance";
  if (x3d == "fieldOfView") return "fov";
  if (x3d == "whichChoice") return "whichChild";
  if (x3d == "fraction") return "set_fraction";
  if (x3d == "value") return "value_changed";
  return {};
}

std::string_view stripped(std::string_view name) {
  if (name.starts_with("set_")) name.remove_prefix(4);
  if (name.ends_with("_changed")) name.remove_suffix(8);
  return name;
}

/// The field of `node` an X3D event name refers to, or null.
Field* findField(const Node& node, std::string_view name) {
  if (Field* f = node.field(name)) return f;
  const std::string_view base = stripped(name);
  if (Field* f = node.field(base)) return f;
  if (Field* f = node.field(std::string(base) + "_changed")) return f;
  if (Field* f = node.field("set_" + std::string(base))) return f;
  const std::string_view a = alias(base);
  return a.empty() ? nullptr : node.field(a);
}

bool nonDecreasing(const std::vector<float>& keys) {
  return std::is_sorted(keys.begin(), keys.end());
}

}  // namespace

void FileReader::readAnimator(pugi::xml_node el) {
  if (!el.attribute("USE").empty()) {
    use(el);  // a reference in a children list: the animator is not part of the graph
    return;
  }
  const Attributes a = attrs(el);
  const std::string_view type = el.name();
  ref_ptr<Animator> node;
  if (type == "TimeSensor") {
    ref_ptr<TimeSensor> t = TimeSensor::create();
    t->cycleInterval = a.getDouble("cycleInterval", 1.0);
    t->loop = a.getBool("loop", false);
    t->startTime = a.getDouble("startTime", 0.0);
    t->stopTime = a.getDouble("stopTime", 0.0);
    t->enabled = a.getBool("enabled", true);
    if (t->cycleInterval.getValue() <= 0.0)
      warn(el, "TimeSensor cycleInterval not positive: its fraction stays 0");
    s_.timeSensors.push_back(t);
    node = t;
  } else {
    const std::vector<float> key = a.getFloats("key");
    bool keysOk = nonDecreasing(key);
    if (!keysOk) warn(el, std::string(type) + " keys decrease: interpolator ignored");
    // Multi-valued interpolators hold key.size() lists of equal length.
    const auto lists = [&](std::size_t values) {
      if (key.empty() || values % key.size() == 0) return true;
      warn(el, std::string(type) + ": " + std::to_string(values) +
                   " key values do not divide into " + std::to_string(key.size()) +
                   " keys: interpolator ignored");
      return false;
    };
    if (type == "PositionInterpolator") {
      ref_ptr<nodes::PositionInterpolator> p = nodes::PositionInterpolator::create();
      if (keysOk) {
        p->key = key;
        p->keyValue = a.getVec3s("keyValue");
      }
      node = p;
    } else if (type == "OrientationInterpolator") {
      ref_ptr<nodes::OrientationInterpolator> p = nodes::OrientationInterpolator::create();
      if (keysOk) {
        p->key = key;
        p->keyValue = a.getRotations("keyValue");
      }
      node = p;
    } else if (type == "ScalarInterpolator") {
      ref_ptr<nodes::ScalarInterpolator> p = nodes::ScalarInterpolator::create();
      if (keysOk) {
        p->key = key;
        p->keyValue = a.getFloats("keyValue");
      }
      node = p;
    } else if (type == "CoordinateInterpolator") {
      ref_ptr<nodes::CoordinateInterpolator> p = nodes::CoordinateInterpolator::create();
      std::vector<Vec3f> values = a.getVec3s("keyValue");
      if (keysOk && lists(values.size())) {
        p->key = key;
        p->keyValue = std::move(values);
      }
      node = p;
    } else {
      ref_ptr<NormalInterpolator> p = NormalInterpolator::create();
      std::vector<Vec3f> values = a.getVec3s("keyValue");
      if (keysOk && lists(values.size())) {
        p->key = key;
        p->keyValue = std::move(values);
      }
      node = p;
    }
  }
  s_.out.animators.push_back(node);
  if (DefEntry* e = define(el, graphEntry(node, node.get()))) e->complete = true;
}

void FileReader::readRoute(pugi::xml_node el) {
  const Attributes a = attrs(el);
  routes_.push_back({a.getString("fromNode"), a.getString("fromField"), a.getString("toNode"),
                     a.getString("toField"), a.line()});
}

void FileReader::resolveRoutes() {
  for (const RouteSpec& r : routes_) {
    const auto from = defs_.find(r.fromNode);
    const auto to = defs_.find(r.toNode);
    if (from == defs_.end() || to == defs_.end()) {
      warnAt(r.line, "ROUTE: no node named '" + (from == defs_.end() ? r.fromNode : r.toNode) +
                         "', ignored");
      continue;
    }
    Node* source = from->second.target;
    if (!source || !dynamic_cast<Animator*>(source)) {
      warnAt(r.line, "ROUTE from " + from->second.type + " '" + r.fromNode +
                         "': only TimeSensors and interpolators drive fields here, ignored");
      continue;
    }
    Field* f = findField(*source, r.fromField);
    if (!f) {
      warnAt(r.line,
             "ROUTE: " + from->second.type + " has no field '" + r.fromField + "', ignored");
      continue;
    }
    connectInto(r, *f, to->second);
  }
}

void FileReader::connectInto(const RouteSpec& r, Field& from, DefEntry& to) {
  const std::string_view field = stripped(r.toField);
  const bool coords =
      (to.type == "Coordinate" || to.type == "CoordinateDouble") && field == "point";
  const bool normals = to.type == "Normal" && field == "vector";
  try {
    if (coords || normals) {
      if (!to.attribute) return;
      for (const std::weak_ptr<GeometryData>& w : to.attribute->users) {
        const std::shared_ptr<GeometryData> g = w.lock();
        if (!g) continue;
        g->deformers.resize(g->parts.size());
        for (std::size_t i = 0; i < g->parts.size(); ++i) {
          if (!g->deformers[i]) {
            g->deformers[i] =
                MeshDeformer::create(g->parts[i], g->coord ? g->coord->v3 : std::vector<Vec3f>{},
                                     g->normal ? g->normal->v3 : std::vector<Vec3f>{});
            s_.out.animators.push_back(g->deformers[i]);
          }
          Field& input = coords ? static_cast<Field&>(g->deformers[i]->set_point)
                                : static_cast<Field&>(g->deformers[i]->set_vector);
          input.connectFrom(from);
        }
      }
      return;
    }
    Field* target = to.target ? findField(*to.target, r.toField) : nullptr;
    if (!target) {
      warnAt(r.line, "ROUTE: " + to.type + " '" + r.toNode + "' has no supported field '" +
                         r.toField + "', ignored");
      return;
    }
    target->connectFrom(from);
  } catch (const Error& e) {
    warnAt(r.line, "ROUTE " + r.fromNode + "." + r.fromField + " TO " + r.toNode + "." + r.toField +
                       " ignored: " + e.what());
  }
}

}  // namespace tg::x3d
