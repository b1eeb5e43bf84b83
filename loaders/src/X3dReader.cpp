// The X3D XML walk: file parsing, grouping nodes, transforms, viewpoints, lights, Inline, and
// the DEF/USE table that turns reuse into shared nodes.
#include "X3dReader.h"

#include <algorithm>
#include <fstream>
#include <iterator>
#include <sstream>

#include "tracegraph/backend/Error.h"
#include "tracegraph/nodes/Camera.h"
#include "tracegraph/nodes/DirectionalLight.h"
#include "tracegraph/nodes/PointLight.h"
#include "tracegraph/nodes/SpotLight.h"
#include "tracegraph/nodes/Switch.h"
#include "tracegraph/nodes/Transform.h"

namespace tg::x3d {
namespace {

bool isAnimator(std::string_view n) {
  return n == "TimeSensor" || n == "PositionInterpolator" || n == "OrientationInterpolator" ||
         n == "ScalarInterpolator" || n == "CoordinateInterpolator" || n == "NormalInterpolator";
}

bool isGrouping(std::string_view n) {
  return n == "Group" || n == "StaticGroup" || n == "Collision" || n == "Anchor" ||
         n == "Billboard" || n == "LOD";
}

/// Nodes that are legal in a scene but mean nothing to a ray tracer: skipped silently.
bool isIgnored(std::string_view n) {
  return n == "NavigationInfo" || n.starts_with("Metadata") || n == "head" || n == "meta" ||
         n == "component" || n == "unit";
}

std::string readFile(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  if (!in) throw Error(p.string() + ": cannot open file");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Messages and DEF/USE

void FileReader::warn(pugi::xml_node el, const std::string& what) {
  warnAt(src_.line(el), what);
}

void FileReader::warnAt(int line, const std::string& what) {
  s_.out.warnings.push_back(src_.where(line) + what);
}

void FileReader::fail(pugi::xml_node el, const std::string& what) const {
  throw Error(src_.where(src_.line(el)) + what);
}

void FileReader::countTriangles(pugi::xml_node el, std::size_t triangles) {
  s_.triangles += triangles;
  if (s_.triangles > s_.options.maxTriangles)
    fail(el, "more than " + std::to_string(s_.options.maxTriangles) + " triangles");
}

DefEntry* FileReader::use(pugi::xml_node el) {
  const std::string name = el.attribute("USE").value();
  const auto it = defs_.find(name);
  if (it == defs_.end()) {
    warn(el, std::string(el.name()) + " USE='" + name + "': no node of that name, skipped");
    return nullptr;
  }
  if (!it->second.complete)
    fail(el, std::string(el.name()) + " USE='" + name + "' inside its own definition (line " +
                 std::to_string(it->second.line) + ")");
  if (it->second.type != el.name()) {
    // Grouping nodes are interchangeable in the graph; anything else of another kind is not.
    const bool bothGroups = (isGrouping(it->second.type) || it->second.type == "Transform") &&
                            (isGrouping(el.name()) || std::string_view(el.name()) == "Transform");
    if (!bothGroups) {
      warn(el,
           std::string(el.name()) + " USE='" + name + "' names a " + it->second.type + ", skipped");
      return nullptr;
    }
  }
  return &it->second;
}

DefEntry* FileReader::define(pugi::xml_node el, DefEntry entry) {
  const pugi::xml_attribute def = el.attribute("DEF");
  if (def.empty()) return nullptr;
  const std::string name = def.value();
  entry.type = el.name();
  entry.line = src_.line(el);
  if (entry.node) entry.node->setName(name);
  if (entry.target && entry.target != entry.node.get()) entry.target->setName(name);
  const auto [it, added] = defs_.insert_or_assign(name, std::move(entry));
  if (!added) warn(el, "DEF='" + name + "' defined again; later USEs get this node");
  return &it->second;
}

// ---------------------------------------------------------------------------------------------
// The walk

ref_ptr<nodes::Separator> FileReader::readScene(pugi::xml_node scene) {
  ref_ptr<nodes::Separator> root = nodes::Separator::create();
  readChildren(scene, *root, 0, false);
  resolveRoutes();
  return root;
}

void FileReader::readChildren(pugi::xml_node el, Group& into, std::size_t depth, bool keepIndices) {
  for (pugi::xml_node c = el.first_child(); c; c = c.next_sibling()) {
    if (c.type() != pugi::node_element) continue;
    ref_ptr<Node> n = readNode(c, depth + 1);
    if (n) {
      into.addChild(n);
    } else if (keepIndices && std::string_view(c.name()) != "ROUTE" &&
               !std::string_view(c.name()).starts_with("Metadata")) {
      // Keeps Switch choices numbered as in the file when a child is dropped.
      into.addChild(nodes::Separator::create());
    }
  }
}

ref_ptr<Node> FileReader::readNode(pugi::xml_node el, std::size_t depth) {
  if (depth > s_.options.maxNesting)
    fail(el, "elements nested deeper than " + std::to_string(s_.options.maxNesting));
  const std::string_view name = el.name();
  if (name == "ROUTE") {
    readRoute(el);
    return nullptr;
  }
  if (isAnimator(name)) {
    readAnimator(el);
    return nullptr;
  }
  if (isIgnored(name)) return nullptr;
  if (!el.attribute("USE").empty()) {
    DefEntry* e = use(el);
    if (!e || !e->node || dynamic_cast<Animator*>(e->node.get())) return nullptr;
    return e->node;
  }
  if (name == "Transform") return readTransform(el, depth);
  if (isGrouping(name)) return readGrouping(el, depth);
  if (name == "Switch") return readSwitch(el, depth);
  if (name == "Shape") return readShape(el, depth);
  if (name == "Viewpoint") return readViewpoint(el);
  if (name == "PointLight" || name == "DirectionalLight" || name == "SpotLight")
    return readLight(el);
  if (name == "Inline") return readInline(el);
  if (name == "Background") {
    readBackground(el);
    return nullptr;
  }
  if (name == "WorldInfo") {
    if (s_.out.title.empty()) s_.out.title = attrs(el).getString("title");
    return nullptr;
  }
  warn(el, "unsupported node " + std::string(name) + " skipped");
  return nullptr;
}

ref_ptr<Node> FileReader::readGrouping(pugi::xml_node el, std::size_t depth) {
  ref_ptr<nodes::Separator> sep = nodes::Separator::create();
  DefEntry* e = define(el, graphEntry(sep, sep.get()));
  if (std::string_view(el.name()) == "LOD") {
    // Without a viewer distance the most detailed level (the first) is the one to trace.
    for (pugi::xml_node c = el.first_child(); c; c = c.next_sibling()) {
      if (c.type() != pugi::node_element || std::string_view(c.name()).starts_with("Metadata"))
        continue;
      if (ref_ptr<Node> n = readNode(c, depth + 1)) {
        sep->addChild(n);
        break;
      }
    }
  } else {
    if (std::string_view(el.name()) == "Billboard")
      warn(el, "Billboard is not turned towards the viewer");
    readChildren(el, *sep, depth, false);
  }
  if (e) e->complete = true;
  return sep;
}

ref_ptr<Node> FileReader::readTransform(pugi::xml_node el, std::size_t depth) {
  const Attributes a = attrs(el);
  ref_ptr<nodes::Transform> t = nodes::Transform::create();
  t->translation = a.getVec3("translation", {});
  t->rotation = a.getRotation("rotation", {});
  t->scale = a.getVec3("scale", {1.0f, 1.0f, 1.0f});
  t->scaleOrientation = a.getRotation("scaleOrientation", {});
  t->center = a.getVec3("center", {});
  ref_ptr<nodes::Separator> sep = nodes::Separator::create();
  sep->addChild(t);
  DefEntry* e = define(el, graphEntry(sep, t.get()));
  readChildren(el, *sep, depth, false);
  if (e) e->complete = true;
  return sep;
}

ref_ptr<Node> FileReader::readSwitch(pugi::xml_node el, std::size_t depth) {
  const Attributes a = attrs(el);
  ref_ptr<nodes::Switch> sw = nodes::Switch::create();
  // X3D calls it whichChoice, VRML97 whichChild.
  sw->whichChild = a.getInt("whichChoice", a.getInt("whichChild", -1));
  DefEntry* e = define(el, graphEntry(sw, sw.get()));
  readChildren(el, *sw, depth, true);
  if (e) e->complete = true;
  return sw;
}

ref_ptr<Node> FileReader::readViewpoint(pugi::xml_node el) {
  const Attributes a = attrs(el);
  ref_ptr<nodes::Camera> cam = nodes::Camera::create();
  cam->position = a.getVec3("position", {0.0f, 0.0f, 10.0f});
  cam->orientation = a.getRotation("orientation", {});
  const float fov = a.getFloat("fieldOfView", 0.785398f);
  if (fov > 0.0f && fov < 3.14159f)
    cam->fov = fov;
  else
    warn(el, "Viewpoint fieldOfView outside (0, pi): default used");
  s_.out.cameras.push_back(cam);
  if (DefEntry* e = define(el, graphEntry(cam, cam.get()))) e->complete = true;
  return cam;
}

ref_ptr<Node> FileReader::readLight(pugi::xml_node el) {
  const Attributes a = attrs(el);
  const std::string_view name = el.name();
  const bool on = a.getBool("on", true);
  const Vec3f c = a.getVec3("color", {1.0f, 1.0f, 1.0f});
  const Color color{c.x, c.y, c.z};
  const float intensity = a.getFloat("intensity", 1.0f);
  ref_ptr<Node> light;
  if (name == "PointLight") {
    ref_ptr<nodes::PointLight> l = nodes::PointLight::create();
    l->on = on, l->color = color, l->intensity = intensity;
    l->location = a.getVec3("location", {});
    l->attenuation = a.getVec3("attenuation", {1.0f, 0.0f, 0.0f});
    light = l;
  } else if (name == "DirectionalLight") {
    ref_ptr<nodes::DirectionalLight> l = nodes::DirectionalLight::create();
    l->on = on, l->color = color, l->intensity = intensity;
    l->direction = a.getVec3("direction", {0.0f, 0.0f, -1.0f});
    light = l;
  } else {
    ref_ptr<nodes::SpotLight> l = nodes::SpotLight::create();
    l->on = on, l->color = color, l->intensity = intensity;
    l->location = a.getVec3("location", {});
    l->direction = a.getVec3("direction", {0.0f, 0.0f, -1.0f});
    l->beamWidth = a.getFloat("beamWidth", 1.570796f);
    l->cutOffAngle = a.getFloat("cutOffAngle", 0.785398f);
    l->attenuation = a.getVec3("attenuation", {1.0f, 0.0f, 0.0f});
    light = l;
  }
  if (DefEntry* e = define(el, graphEntry(light, light.get()))) e->complete = true;
  return light;
}

void FileReader::readBackground(pugi::xml_node el) {
  const std::vector<Color> sky = attrs(el).getColors("skyColor");
  if (s_.out.hasBackground || sky.empty()) return;
  s_.out.background = {sky[0].r, sky[0].g, sky[0].b};
  s_.out.hasBackground = true;
}

ref_ptr<Node> FileReader::readInline(pugi::xml_node el) {
  const Attributes a = attrs(el);
  if (!a.getBool("load", true)) return nullptr;
  std::filesystem::path found;
  for (const std::string& url : a.getStrings("url")) {
    if (url.empty() || url.find("://") != std::string::npos) continue;
    const std::filesystem::path p = src_.dir() / url;
    std::error_code ec;
    if (std::filesystem::is_regular_file(p, ec)) {
      found = p;
      break;
    }
  }
  if (found.empty()) {
    warn(el, "Inline: no url names an existing local file, skipped");
    return nullptr;
  }
  std::error_code ec;
  std::filesystem::path key = std::filesystem::weakly_canonical(found, ec);
  if (ec) key = found.lexically_normal();
  if (std::find(s_.inlineStack.begin(), s_.inlineStack.end(), key) != s_.inlineStack.end()) {
    std::string chain;
    for (const auto& p : s_.inlineStack) chain += p.filename().string() + " -> ";
    fail(el, "Inline cycle: " + chain + key.filename().string());
  }
  if (inlineDepth_ + 1 > s_.options.maxInlineDepth)
    fail(el, "Inline nested deeper than " + std::to_string(s_.options.maxInlineDepth));
  ref_ptr<nodes::Separator> sep;
  if (const auto it = s_.inlineCache.find(key); it != s_.inlineCache.end()) {
    sep = it->second;  // inlined again: the same subgraph, one more instance
  } else {
    s_.inlineStack.push_back(key);
    const std::string text = readFile(found);
    sep = readX3dText(s_, text, found.string(), found.parent_path(), inlineDepth_ + 1);
    s_.inlineStack.pop_back();
    s_.inlineCache.emplace(key, sep);
  }
  if (DefEntry* e = define(el, graphEntry(sep, sep.get()))) e->complete = true;
  return sep;
}

// ---------------------------------------------------------------------------------------------
// Files

ref_ptr<nodes::Separator> readX3dText(Session& session, std::string_view text,
                                      const std::string& name, const std::filesystem::path& dir,
                                      std::size_t inlineDepth) {
  const SourceText src(name, dir, text);
  pugi::xml_document doc;
  const pugi::xml_parse_result r =
      doc.load_buffer(text.data(), text.size(), pugi::parse_default, pugi::encoding_utf8);
  if (!r) throw Error(src.where(src.lineAt(r.offset)) + "malformed XML: " + r.description());
  const pugi::xml_node top = doc.document_element();
  pugi::xml_node scene;
  if (std::string_view(top.name()) == "X3D")
    scene = top.child("Scene");
  else if (std::string_view(top.name()) == "Scene")
    scene = top;
  else
    throw Error(src.where(top ? src.line(top) : 1) + "not an X3D file (root element '" +
                top.name() + "', expected X3D)");
  if (!scene) throw Error(src.where(src.line(top)) + "X3D file without a Scene element");
  FileReader reader(session, src, inlineDepth);
  return reader.readScene(scene);
}

}  // namespace tg::x3d

namespace tg {
namespace {

double animationEnd(const x3d::TimeSensor& t) {
  const double start = t.startTime.getValue(), stop = t.stopTime.getValue();
  const double cycle = std::max(0.0, t.cycleInterval.getValue());
  double end = start + cycle;
  if (stop > start) end = t.loop.getValue() ? stop : std::min(end, stop);
  return std::max(0.0, end);
}

LoadedScene load(std::string_view text, const std::filesystem::path& dir, const std::string& name,
                 const X3dOptions& options, const std::filesystem::path* file) {
  LoadedScene out;
  out.fileName = name;
  out.textureFolders.push_back(dir);
  x3d::Session session(options, out);
  if (file) {
    std::error_code ec;
    std::filesystem::path key = std::filesystem::weakly_canonical(*file, ec);
    session.inlineStack.push_back(ec ? file->lexically_normal() : key);
  }
  out.root = x3d::readX3dText(session, text, name, dir, 0);
  for (const ref_ptr<x3d::TimeSensor>& t : session.timeSensors)
    if (!t->fraction_changed.connections().empty() || !t->time.connections().empty())
      out.animationDuration = std::max(out.animationDuration, animationEnd(*t));
  return out;
}

}  // namespace

LoadedScene loadX3d(const std::filesystem::path& file, const X3dOptions& options) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) throw Error(file.string() + ": no such file");
  const std::string text = x3d::readFile(file);
  return load(text, file.parent_path(), file.string(), options, &file);
}

LoadedScene loadX3dString(std::string_view text, const std::filesystem::path& baseDir,
                          const std::string& name, const X3dOptions& options) {
  return load(text, baseDir, name, options, nullptr);
}

}  // namespace tg
