// A small JSON reader for the glTF pre-check: node graph sanity (Assimp recurses into node
// children without cycle detection), the animation samplers' interpolation (Assimp keeps
// only the key values) and the cameras' vertical field of view.
#include <charconv>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>

#include "AssimpImpl.h"
#include "tracegraph/backend/Error.h"

namespace tg::assimp {
namespace {

struct Json {
  enum class Type { Null, Bool, Number, String, Array, Object } type = Type::Null;
  double number = 0.0;
  std::string string;
  std::vector<Json> array;
  // An object's members as two parallel lists: a vector of pairs holding Json would need Json
  // complete where it is declared, which the standard guarantees for std::vector<Json> only.
  std::vector<std::string> keys;
  std::vector<Json> values;

  const Json* get(std::string_view k) const {
    for (std::size_t i = 0; i < keys.size(); ++i)
      if (keys[i] == k) return &values[i];
    return nullptr;
  }
  /// Elements of an array member (empty when absent or not an array).
  const std::vector<Json>& items(std::string_view k) const {
    static const std::vector<Json> none;
    const Json* v = get(k);
    return v && v->type == Type::Array ? v->array : none;
  }
  /// An integer member, or -1 when absent or not a non-negative integer.
  long long index(std::string_view k) const {
    const Json* v = get(k);
    if (!v || v->type != Type::Number || v->number < 0 || v->number > 1e15 ||
        v->number != static_cast<double>(static_cast<long long>(v->number)))
      return -1;
    return static_cast<long long>(v->number);
  }
  std::string text(std::string_view k) const {
    const Json* v = get(k);
    return v && v->type == Type::String ? v->string : std::string();
  }
};

class Parser {
 public:
  explicit Parser(std::string_view s) : s_(s) {}
  Json parse() {
    Json v = value(0);
    skip();
    if (i_ != s_.size()) fail("trailing characters");
    return v;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw Error("malformed JSON at byte " + std::to_string(i_) + ": " + what);
  }
  void skip() {
    while (i_ < s_.size() && (s_[i_] == ' ' || s_[i_] == '\t' || s_[i_] == '\n' || s_[i_] == '\r'))
      ++i_;
  }
  bool eat(char c) {
    skip();
    if (i_ < s_.size() && s_[i_] == c) {
      ++i_;
      return true;
    }
    return false;
  }
  Json value(int depth) {
    if (depth > 128) fail("nested too deeply");
    skip();
    if (i_ >= s_.size()) fail("unexpected end");
    Json v;
    const char c = s_[i_];
    if (c == '{') {
      ++i_;
      v.type = Json::Type::Object;
      if (eat('}')) return v;
      do {
        skip();
        std::string k = str();
        if (!eat(':')) fail("expected ':'");
        v.keys.push_back(std::move(k));
        v.values.push_back(value(depth + 1));
      } while (eat(','));
      if (!eat('}')) fail("expected '}'");
    } else if (c == '[') {
      ++i_;
      v.type = Json::Type::Array;
      if (eat(']')) return v;
      do v.array.push_back(value(depth + 1));
      while (eat(','));
      if (!eat(']')) fail("expected ']'");
    } else if (c == '"') {
      v.type = Json::Type::String;
      v.string = str();
    } else if (s_.substr(i_, 4) == "true" || s_.substr(i_, 4) == "null") {
      v.type = s_[i_] == 't' ? Json::Type::Bool : Json::Type::Null;
      i_ += 4;
    } else if (s_.substr(i_, 5) == "false") {
      v.type = Json::Type::Bool;
      i_ += 5;
    } else {
      v.type = Json::Type::Number;
      const auto [end, ec] = std::from_chars(s_.data() + i_, s_.data() + s_.size(), v.number);
      if (ec != std::errc()) fail("unexpected character");
      i_ = static_cast<std::size_t>(end - s_.data());
    }
    return v;
  }
  std::string str() {
    if (i_ >= s_.size() || s_[i_] != '"') fail("expected a string");
    ++i_;
    std::string out;
    while (i_ < s_.size() && s_[i_] != '"') {
      if (s_[i_] == '\\') {
        if (++i_ >= s_.size()) break;
        const char e = s_[i_];
        // \uXXXX is kept verbatim: names only need to compare equal, never to print.
        out += e == 'n' ? '\n' : e == 't' ? '\t' : e;
      } else {
        out += s_[i_];
      }
      ++i_;
    }
    if (i_ >= s_.size()) fail("unterminated string");
    ++i_;
    return out;
  }

  std::string_view s_;
  std::size_t i_ = 0;
};

std::string jsonText(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(file.string() + ": cannot open file");
  std::ostringstream ss;
  ss << in.rdbuf();
  std::string data = ss.str();
  if (data.size() < 4 || data.compare(0, 4, "glTF") != 0) return data;
  // GLB: 12-byte header, then chunks of (length, type, data); the first must be JSON.
  const auto u32 = [&](std::size_t at) {
    std::uint32_t v = 0;
    if (at + 4 > data.size()) throw Error(file.string() + ": truncated GLB header");
    std::memcpy(&v, data.data() + at, 4);
    return v;
  };
  if (u32(4) != 2)
    throw Error(file.string() + ": GLB version " + std::to_string(u32(4)) + " (2 expected)");
  const std::uint32_t length = u32(12), type = u32(16);
  if (type != 0x4E4F534Au || 20ull + length > data.size())
    throw Error(file.string() + ": GLB without a complete JSON chunk");
  return data.substr(20, length);
}

}  // namespace

GltfInfo readGltfInfo(const std::filesystem::path& file) {
  const std::string name = file.string();
  Json root;
  try {
    root = Parser(jsonText(file)).parse();
  } catch (const Error& e) {
    const std::string what = e.what();
    throw Error(what.starts_with(name) ? what : name + ": " + what);
  }
  if (root.type != Json::Type::Object) throw Error(name + ": glTF JSON is not an object");
  GltfInfo info;
  const std::vector<Json>& nodes = root.items("nodes");
  const std::size_t meshes = root.items("meshes").size(), cameras = root.items("cameras").size();
  const auto bad = [&](const std::string& what) { throw Error(name + ": " + what); };
  std::vector<int> parent(nodes.size(), -1);
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const std::string n = nodes[i].text("name");
    info.nodeNames.push_back(n.empty() ? "nodes[" + std::to_string(i) + "]" : n);
    if (nodes[i].get("mesh") && nodes[i].index("mesh") >= static_cast<long long>(meshes))
      bad("node " + std::to_string(i) + " names mesh " + std::to_string(nodes[i].index("mesh")) +
          " of " + std::to_string(meshes));
    if (nodes[i].get("camera") && nodes[i].index("camera") >= static_cast<long long>(cameras))
      bad("node " + std::to_string(i) + " names a missing camera");
    for (const Json& c : nodes[i].items("children")) {
      const long long ci = c.type == Json::Type::Number ? static_cast<long long>(c.number) : -1;
      if (ci < 0 || ci >= static_cast<long long>(nodes.size()) ||
          c.number != static_cast<double>(ci))
        bad("node " + std::to_string(i) + " has a child index out of range");
      if (static_cast<std::size_t>(ci) == i || parent[static_cast<std::size_t>(ci)] != -1)
        bad("recursive node reference: node " + std::to_string(ci) +
            (static_cast<std::size_t>(ci) == i ? " is its own child" : " has two parents"));
      parent[static_cast<std::size_t>(ci)] = static_cast<int>(i);
    }
  }
  // With one parent each, a cycle is a parent chain longer than the node count.
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    std::size_t steps = 0;
    for (int p = parent[i]; p != -1; p = parent[static_cast<std::size_t>(p)])
      if (++steps > nodes.size())
        bad("recursive node reference: node " + std::to_string(i) + " is its own ancestor");
  }
  const std::vector<Json>& scenes = root.items("scenes");
  const long long sceneIndex = root.get("scene") ? root.index("scene") : 0;
  if (scenes.empty() || sceneIndex < 0 || sceneIndex >= static_cast<long long>(scenes.size()))
    bad("no scene to load");
  const std::vector<Json>& roots = scenes[static_cast<std::size_t>(sceneIndex)].items("nodes");
  if (roots.empty()) bad("the scene has no nodes");
  for (const Json& r : roots)
    if (r.type != Json::Type::Number || r.number < 0 ||
        r.number >= static_cast<double>(nodes.size()))
      bad("scene node index out of range");

  // Buffer views and accessors must stay inside their buffers: Assimp reads some wrongly
  // typed members as defaults instead of failing.
  const std::vector<Json>& buffers = root.items("buffers");
  const std::vector<Json>& views = root.items("bufferViews");
  for (std::size_t i = 0; i < views.size(); ++i) {
    const long long b = views[i].index("buffer"), length = views[i].index("byteLength");
    const long long offset = views[i].get("byteOffset") ? views[i].index("byteOffset") : 0;
    if (b < 0 || b >= static_cast<long long>(buffers.size()) || length < 0 || offset < 0 ||
        offset + length > buffers[static_cast<std::size_t>(b)].index("byteLength"))
      bad("bufferView " + std::to_string(i) + " lies outside its buffer");
  }
  const std::vector<Json>& accessors = root.items("accessors");
  for (std::size_t i = 0; i < accessors.size(); ++i) {
    const Json& a = accessors[i];
    const long long type = a.index("componentType"), count = a.index("count");
    const long long bytes = type == 5120 || type == 5121   ? 1
                            : type == 5122 || type == 5123 ? 2
                            : type == 5125 || type == 5126 ? 4
                                                           : 0;
    const std::string t = a.text("type");
    const long long comps = t == "SCALAR" ? 1
                            : t == "VEC2" ? 2
                            : t == "VEC3" ? 3
                            : t == "VEC4" ? 4
                            : t == "MAT2" ? 4
                            : t == "MAT3" ? 9
                            : t == "MAT4" ? 16
                                          : 0;
    const std::string what = "accessor " + std::to_string(i);
    if (bytes == 0 || comps == 0 || count < 1)
      bad(what + " has a missing or wrongly typed componentType, type or count");
    if (!a.get("bufferView")) continue;  // all zeros (or sparse), nothing to overrun
    const long long v = a.index("bufferView");
    const long long offset = a.get("byteOffset") ? a.index("byteOffset") : 0;
    if (v < 0 || v >= static_cast<long long>(views.size()) || offset < 0)
      bad(what + " names a missing bufferView");
    const Json& view = views[static_cast<std::size_t>(v)];
    const long long stride = view.get("byteStride") ? view.index("byteStride") : bytes * comps;
    if (stride < bytes * comps || count > (1ll << 40) / stride ||
        offset + (count - 1) * stride + bytes * comps > view.index("byteLength"))
      bad(what + " reads past the end of bufferView " + std::to_string(v));
  }

  std::map<std::string, int> nameCount;
  for (const std::string& n : info.nodeNames) ++nameCount[n];
  for (const Json& anim : root.items("animations")) {
    auto& map = info.interpolation.emplace_back();
    const std::vector<Json>& samplers = anim.items("samplers");
    for (const Json& ch : anim.items("channels")) {
      const long long s = ch.index("sampler");
      const Json* target = ch.get("target");
      if (!target || s < 0 || s >= static_cast<long long>(samplers.size())) continue;
      const long long node = target->index("node");
      if (node < 0 || node >= static_cast<long long>(nodes.size())) continue;
      const std::string& nodeName = info.nodeNames[static_cast<std::size_t>(node)];
      if (nameCount[nodeName] != 1) continue;
      const std::string mode = samplers[static_cast<std::size_t>(s)].text("interpolation");
      map[{nodeName, target->text("path")}] = mode == "STEP"          ? Interpolation::Step
                                              : mode == "CUBICSPLINE" ? Interpolation::CubicSpline
                                                                      : Interpolation::Linear;
    }
  }
  const std::vector<Json>& cams = root.items("cameras");
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const long long c = nodes[i].index("camera");
    if (c < 0 || nameCount[info.nodeNames[i]] != 1) continue;
    const Json& cam = cams[static_cast<std::size_t>(c)];
    GltfInfo::Camera out;
    out.perspective = cam.text("type") != "orthographic";
    if (const Json* p = cam.get("perspective")) {
      if (const Json* v = p->get("yfov"); v && v->type == Json::Type::Number) out.yfov = v->number;
      if (const Json* v = p->get("aspectRatio"); v && v->type == Json::Type::Number)
        out.aspect = v->number;
      if (const Json* v = p->get("znear"); v && v->type == Json::Type::Number)
        out.znear = v->number;
    }
    info.cameras[info.nodeNames[i]] = out;
  }
  return info;
}

}  // namespace tg::assimp
