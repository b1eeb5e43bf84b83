#include "tracegraph/backend/OpenRT.h"

#include <cmath>
#include <exception>
#include <new>
#include <numeric>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "tracegraph/backend/Error.h"

namespace tg {
namespace {

/// GL-style error state: the oldest unreported code and the most recent message.
struct ErrorSlot {
  RTerror pending = RT_NO_ERROR;
  std::string message;
};

/// A rejected call, thrown by the checks below and turned into an RTerror by runCall().
struct Rejection {
  RTerror code;
  std::string message;
};

/// Rejects the running call; runCall() records `code` and the message prefixed with the call.
[[noreturn]] void reject(RTerror code, std::string message) {
  throw Rejection{code, std::move(message)};
}

/// True for numbers that are neither NaN nor infinite.
bool finite(float x) {
  return std::isfinite(x);
}

}  // namespace

/// Everything a context owns. The open object definition is kept apart from the scene until
/// rtEndObject, so that a rejected or abandoned definition never reaches it.
struct RTcontextState {
  struct Definition {
    RTuint object = RT_INVALID_ID;
    TriangleMesh mesh;  ///< positions, plus one normal and one uv per vertex until rtEndObject
    bool inPrimitive = false;
    std::size_t primitiveStart = 0;  ///< vertex count at the last rtBegin
    Vec3f normal{0.0f, 0.0f, 1.0f};  ///< GL's default current normal
    Vec2f uv;
    bool normalSet = false, uvSet = false;  ///< rtNormal3f / rtTexCoord2f called so far
    bool anyNormal = false, anyUv = false;  ///< a vertex was emitted after one of them
    bool spoiled = false;
    std::string firstError;
  };

  explicit RTcontextState(const SceneOptions& options) : scene(options) {}

  Scene scene;
  ErrorSlot errors;
  Affine3d matrix;              ///< current matrix, composed in double
  std::vector<Affine3d> stack;  ///< saved matrices (excluding the current one)
  std::optional<Definition> definition;
};

namespace {

/// The calling thread's current context, as in GL.
thread_local RTcontext tCurrent = nullptr;
/// Errors of calls made while this thread had no current context.
thread_local ErrorSlot tNoContextErrors;

/// Records an error of `call` on `ctx` (or the thread's no-context slot) and spoils the open
/// definition, if any.
void record(RTcontextState* ctx, RTerror code, const char* call, const std::string& what) {
  ErrorSlot& slot = ctx ? ctx->errors : tNoContextErrors;
  if (slot.pending == RT_NO_ERROR) slot.pending = code;
  try {
    std::string message = std::string(call) + ": " + what;
    // The first error inside a definition explains why rtEndObject will discard it.
    if (ctx && ctx->definition && !ctx->definition->spoiled) {
      ctx->definition->spoiled = true;
      ctx->definition->firstError = message;
    }
    slot.message = std::move(message);
  } catch (const std::bad_alloc&) {
    if (ctx && ctx->definition) ctx->definition->spoiled = true;
    slot.message.clear();  // the code above still tells the caller what went wrong
  }
}

/// Runs the body of API call `call` on the current context and converts every failure into a
/// recorded error, so that no exception crosses the C-style interface. Bodies check all their
/// arguments before changing anything, and Scene edits leave the scene unchanged when they throw.
template <typename Body>
auto runCall(const char* call, Body&& body) -> decltype(body(std::declval<RTcontextState&>())) {
  using Result = decltype(body(std::declval<RTcontextState&>()));
  RTcontextState* ctx = tCurrent;
  try {
    if (!ctx) reject(RT_INVALID_OPERATION, "no current context");
    return body(*ctx);
  } catch (const Rejection& r) {
    record(ctx, r.code, call, r.message);
  } catch (const Error& e) {
    record(ctx, RT_INVALID_VALUE, call, e.what());
  } catch (const std::bad_alloc&) {
    record(ctx, RT_OUT_OF_MEMORY, call, "out of memory");
  } catch (const std::exception& e) {
    record(ctx, RT_INVALID_OPERATION, call, e.what());
  }
  if constexpr (std::is_void_v<Result>) {
    return;
  } else {
    return RT_INVALID_ID;
  }
}

/// "object N, vertex M", where M is the index the next vertex would get.
std::string objectText(const RTcontextState::Definition& def) {
  return "object " + std::to_string(def.object) + ", vertex " +
         std::to_string(def.mesh.positions.size());
}

/// The open definition inside rtBegin/rtEnd, or a rejection naming what is missing.
RTcontextState::Definition& primitiveBlock(RTcontextState& ctx) {
  if (!ctx.definition || !ctx.definition->inPrimitive)
    reject(RT_INVALID_OPERATION, "called outside rtBegin/rtEnd");
  return *ctx.definition;
}

/// The open definition, or a rejection when none is open.
RTcontextState::Definition& openDefinition(RTcontextState& ctx) {
  if (!ctx.definition) reject(RT_INVALID_OPERATION, "called outside rtBeginObject/rtEndObject");
  return *ctx.definition;
}

/// Rejects calls that make no sense while an object is being defined.
void requireNoDefinition(const RTcontextState& ctx) {
  if (ctx.definition)
    reject(RT_INVALID_OPERATION,
           "not allowed inside the definition of object " + std::to_string(ctx.definition->object));
}

/// Rejects ids that do not name a live object of the scene.
void requireObject(const RTcontextState& ctx, RTuint id) {
  try {
    (void)ctx.scene.objectUsage(id);
  } catch (const Error&) {
    reject(RT_INVALID_VALUE, "unknown object id " + std::to_string(id));
  }
}

/// Right-multiplies the current matrix by `m` (GL order), refusing results that overflow.
void multiply(RTcontextState& ctx, const Affine3d& m) {
  const Affine3d result = ctx.matrix * m;
  if (!result.isFinite()) reject(RT_INVALID_VALUE, "resulting matrix is not finite");
  ctx.matrix = result;
}

/// The checks an instance matrix needs beyond Scene's own: the scene traces with a float copy,
/// which must not overflow to infinity.
void requireInstanceMatrix(const Affine3d& m) {
  if (!m.isFinite() || !Affine3f(m).isFinite())
    reject(RT_INVALID_VALUE, "current matrix does not fit in float");
  if (m.isSingular()) reject(RT_INVALID_VALUE, "current matrix is singular (zero scale?)");
}

}  // namespace

RTcontext rtCreateContext(const SceneOptions& options) {
  try {
    return new RTcontextState(options);
  } catch (const std::exception&) {
    return nullptr;
  }
}

void rtDestroyContext(RTcontext context) {
  if (tCurrent == context) tCurrent = nullptr;
  delete context;
}

void rtMakeCurrent(RTcontext context) {
  tCurrent = context;
}

RTcontext rtGetCurrentContext() {
  return tCurrent;
}

RTerror rtGetError() {
  ErrorSlot& slot = tCurrent ? tCurrent->errors : tNoContextErrors;
  return std::exchange(slot.pending, RT_NO_ERROR);
}

const char* rtGetErrorString() {
  return (tCurrent ? tCurrent->errors : tNoContextErrors).message.c_str();
}

RTuint rtNewObject(RTenum usage) {
  return runCall("rtNewObject", [&](RTcontextState& ctx) -> RTuint {
    ObjectUsage u = ObjectUsage::Static;
    if (usage == RT_RIGID) {
      u = ObjectUsage::Rigid;
    } else if (usage == RT_DEFORMING) {
      u = ObjectUsage::Deforming;
    } else if (usage != RT_STATIC) {
      reject(RT_INVALID_ENUM,
             "usage " + std::to_string(usage) + " is not RT_STATIC, RT_RIGID or RT_DEFORMING");
    }
    return ctx.scene.createObject(TriangleMesh{}, u);
  });
}

void rtBeginObject(RTuint id) {
  runCall("rtBeginObject", [&](RTcontextState& ctx) {
    requireNoDefinition(ctx);
    requireObject(ctx, id);
    RTcontextState::Definition def;
    def.object = id;
    ctx.definition = std::move(def);
  });
}

void rtEndObject() {
  runCall("rtEndObject", [&](RTcontextState& ctx) {
    if (!ctx.definition) reject(RT_INVALID_OPERATION, "no object definition is open");
    // Closed whatever happens next: the caller's following calls are outside the definition.
    RTcontextState::Definition def = std::move(*ctx.definition);
    ctx.definition.reset();
    const std::string discarded = "object " + std::to_string(def.object) + " discarded: ";
    if (def.inPrimitive) reject(RT_INVALID_OPERATION, discarded + "called inside rtBegin/rtEnd");
    if (def.spoiled)
      reject(RT_INVALID_OPERATION, discarded + "an earlier call failed (" + def.firstError + ")");
    TriangleMesh& mesh = def.mesh;
    mesh.indices.resize(mesh.positions.size());
    std::iota(mesh.indices.begin(), mesh.indices.end(), 0u);
    if (!def.anyNormal) mesh.normals.clear();
    if (!def.anyUv) mesh.uvs.clear();
    ctx.scene.setObjectMesh(def.object, std::move(mesh));
  });
}

void rtBegin(RTenum mode) {
  runCall("rtBegin", [&](RTcontextState& ctx) {
    RTcontextState::Definition& def = openDefinition(ctx);
    if (def.inPrimitive) reject(RT_INVALID_OPERATION, "already inside rtBegin/rtEnd");
    if (mode != RT_TRIANGLES)
      reject(RT_INVALID_ENUM, "mode " + std::to_string(mode) + " is not RT_TRIANGLES");
    def.inPrimitive = true;
    def.primitiveStart = def.mesh.positions.size();
  });
}

void rtEnd() {
  runCall("rtEnd", [&](RTcontextState& ctx) {
    if (!ctx.definition || !ctx.definition->inPrimitive)
      reject(RT_INVALID_OPERATION, "called without rtBegin");
    RTcontextState::Definition& def = *ctx.definition;
    def.inPrimitive = false;
    const std::size_t count = def.mesh.positions.size() - def.primitiveStart;
    if (count % 3 != 0)
      reject(RT_INVALID_OPERATION, std::to_string(count) +
                                       " vertices do not form whole triangles (object " +
                                       std::to_string(def.object) + ")");
  });
}

void rtVertex3f(float x, float y, float z) {
  runCall("rtVertex3f", [&](RTcontextState& ctx) {
    RTcontextState::Definition& def = primitiveBlock(ctx);
    if (!finite(x) || !finite(y) || !finite(z))
      reject(RT_INVALID_VALUE, "vertex is NaN or infinite (" + objectText(def) + ")");
    def.mesh.positions.push_back({x, y, z});
    def.mesh.normals.push_back(def.normal);
    def.mesh.uvs.push_back(def.uv);
    def.anyNormal = def.anyNormal || def.normalSet;
    def.anyUv = def.anyUv || def.uvSet;
  });
}

void rtNormal3f(float x, float y, float z) {
  runCall("rtNormal3f", [&](RTcontextState& ctx) {
    RTcontextState::Definition& def = openDefinition(ctx);
    if (!finite(x) || !finite(y) || !finite(z))
      reject(RT_INVALID_VALUE, "normal is NaN or infinite (" + objectText(def) + ")");
    def.normal = {x, y, z};
    def.normalSet = true;
  });
}

void rtTexCoord2f(float u, float v) {
  runCall("rtTexCoord2f", [&](RTcontextState& ctx) {
    RTcontextState::Definition& def = openDefinition(ctx);
    if (!finite(u) || !finite(v))
      reject(RT_INVALID_VALUE, "texture coordinate is NaN or infinite (" + objectText(def) + ")");
    def.uv = {u, v};
    def.uvSet = true;
  });
}

void rtPushMatrix() {
  runCall("rtPushMatrix", [&](RTcontextState& ctx) {
    if (ctx.stack.size() + 1 >= static_cast<std::size_t>(RT_MAX_MATRIX_STACK_DEPTH))
      reject(RT_STACK_OVERFLOW,
             "matrix stack is full (" + std::to_string(RT_MAX_MATRIX_STACK_DEPTH) + " matrices)");
    ctx.stack.push_back(ctx.matrix);
  });
}

void rtPopMatrix() {
  runCall("rtPopMatrix", [&](RTcontextState& ctx) {
    if (ctx.stack.empty()) reject(RT_STACK_UNDERFLOW, "matrix stack is empty");
    ctx.matrix = ctx.stack.back();
    ctx.stack.pop_back();
  });
}

void rtLoadIdentity() {
  runCall("rtLoadIdentity", [&](RTcontextState& ctx) { ctx.matrix = Affine3d::identity(); });
}

void rtTranslatef(float x, float y, float z) {
  runCall("rtTranslatef", [&](RTcontextState& ctx) {
    if (!finite(x) || !finite(y) || !finite(z))
      reject(RT_INVALID_VALUE, "translation is NaN or infinite");
    multiply(ctx, Affine3d::translation(Vec3d(Vec3f(x, y, z))));
  });
}

void rtRotatef(float degrees, float x, float y, float z) {
  runCall("rtRotatef", [&](RTcontextState& ctx) {
    if (!finite(degrees) || !finite(x) || !finite(y) || !finite(z))
      reject(RT_INVALID_VALUE, "angle or axis is NaN or infinite");
    multiply(ctx, Affine3d::rotation(Vec3d(Vec3f(x, y, z)), static_cast<double>(degrees)));
  });
}

void rtScalef(float x, float y, float z) {
  runCall("rtScalef", [&](RTcontextState& ctx) {
    if (!finite(x) || !finite(y) || !finite(z))
      reject(RT_INVALID_VALUE, "scale factor is NaN or infinite");
    multiply(ctx, Affine3d::scaling(Vec3d(Vec3f(x, y, z))));
  });
}

void rtMultMatrixf(const float m[16]) {
  runCall("rtMultMatrixf", [&](RTcontextState& ctx) {
    if (!m) reject(RT_INVALID_VALUE, "matrix pointer is null");
    for (int i = 0; i < 16; ++i)
      if (!finite(m[i]))
        reject(RT_INVALID_VALUE, "element " + std::to_string(i) + " is NaN or infinite");
    // Column-major like OpenGL: element (row r, column c) is m[4 * c + r].
    if (m[3] != 0.0f || m[7] != 0.0f || m[11] != 0.0f || m[15] != 1.0f)
      reject(RT_INVALID_VALUE, "last row is not (0, 0, 0, 1); projective matrices are not affine");
    Affine3d a;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) a.m[r][c] = static_cast<double>(m[4 * c + r]);
    multiply(ctx, a);
  });
}

void rtGetMatrixd(double m[16]) {
  runCall("rtGetMatrixd", [&](RTcontextState& ctx) {
    if (!m) reject(RT_INVALID_VALUE, "matrix pointer is null");
    for (int c = 0; c < 4; ++c) {
      for (int r = 0; r < 3; ++r) m[4 * c + r] = ctx.matrix.m[r][c];
      m[4 * c + 3] = c == 3 ? 1.0 : 0.0;
    }
  });
}

RTuint rtInstantiateObject(RTuint id) {
  return runCall("rtInstantiateObject", [&](RTcontextState& ctx) -> RTuint {
    requireNoDefinition(ctx);
    requireObject(ctx, id);
    requireInstanceMatrix(ctx.matrix);
    return ctx.scene.createInstance(id, ctx.matrix);
  });
}

void rtSetInstanceMatrix(RTuint instance) {
  runCall("rtSetInstanceMatrix", [&](RTcontextState& ctx) {
    requireNoDefinition(ctx);
    try {
      (void)ctx.scene.instanceObject(instance);
    } catch (const Error&) {
      reject(RT_INVALID_VALUE, "unknown instance id " + std::to_string(instance));
    }
    requireInstanceMatrix(ctx.matrix);
    ctx.scene.setInstanceTransform(instance, ctx.matrix);
  });
}

void rtCommit() {
  runCall("rtCommit", [&](RTcontextState& ctx) {
    requireNoDefinition(ctx);
    (void)ctx.scene.commit();
  });
}

const Scene& rtGetScene() {
  RTcontextState* ctx = tCurrent;
  if (ctx) return ctx->scene;
  record(nullptr, RT_INVALID_OPERATION, "rtGetScene", "no current context");
  // Built on first use and never edited afterwards, so concurrent readers are safe.
  static Scene empty;
  static const bool committed = (empty.commit(), true);
  (void)committed;
  return empty;
}

}  // namespace tg
