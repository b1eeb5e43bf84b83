/// @file OpenRT.h
/// An OpenRT-style immediate-mode API on top of tg::Scene, in the manner of OpenGL: objects are
/// defined like display lists (rtBeginObject ... rtEndObject with rtBegin/rtVertex3f/rtEnd
/// inside), placed with rtInstantiateObject under the current matrix of a GL-like matrix stack,
/// and published by rtCommit. The system of Wald, Benthin and Slusallek (2003) was driven
/// through the OpenRT API; this layer offers the same way of describing scenes.
///
/// Contexts. Every call works on the calling thread's current context, set by rtMakeCurrent
/// (like GL, the current context is per thread). A context owns one tg::Scene; a context must be
/// current on at most one thread at a time, and the scene is traced through rtGetScene().
///
/// Errors. No call throws. A rejected call leaves the scene and the matrix stack as they were and
/// records an RTerror and a message that starts with the call's name, e.g. "rtVertex3f: vertex is
/// NaN or infinite (object 3, vertex 7)". As in GL, rtGetError returns the oldest error not yet
/// reported and clears it; rtGetErrorString returns the message of the most recent error. A call
/// rejected while an object definition is open also spoils that definition: rtEndObject then
/// discards it (the object keeps its previous mesh) and reports why, so a half-right mesh never
/// reaches the scene. A rejected rtEnd or rtEndObject still closes the block it was meant to
/// close, so that one mistake does not turn every later call into an error.
///
/// No current context. Calls made without a current context do nothing, return RT_INVALID_ID
/// where they return an id, and record RT_INVALID_OPERATION ("<call>: no current context") in a
/// per-thread slot that rtGetError/rtGetErrorString read while no context is current.
/// rtGetScene() then returns an empty, committed scene.
#pragma once

#include <cstdint>

#include "tracegraph/backend/Scene.h"

namespace tg {

/// Opaque context state (defined in OpenRT.cpp).
struct RTcontextState;
/// Handle of a context; null is "no context".
using RTcontext = RTcontextState*;
/// Object and instance ids; equal to the tg::Scene ObjectId/InstanceId they denote, so hit
/// records from rtGetScene() can be matched against them directly.
using RTuint = std::uint32_t;

/// Returned instead of an id by calls that fail.
inline constexpr RTuint RT_INVALID_ID = 0xFFFFFFFFu;
/// Maximum depth of the matrix stack, counting the current matrix (GL guarantees 32).
inline constexpr int RT_MAX_MATRIX_STACK_DEPTH = 64;

/// Symbolic constants passed to calls.
enum RTenum : std::uint32_t {
  RT_TRIANGLES = 0x0004,  ///< rtBegin: every three vertices form a triangle
  RT_STATIC = 0x8000,     ///< rtNewObject: geometry never changes (SAH kd-tree)
  RT_RIGID = 0x8001,      ///< rtNewObject: moved only through instances (SAH kd-tree)
  RT_DEFORMING = 0x8002,  ///< rtNewObject: redefined often (fast kd-tree builder)
};

/// Error codes; the values are OpenGL's so that existing GL error printers work.
enum RTerror : std::uint32_t {
  RT_NO_ERROR = 0,
  RT_INVALID_ENUM = 0x0500,       ///< an RTenum argument not accepted by the call
  RT_INVALID_VALUE = 0x0501,      ///< NaN/Inf numbers, unknown ids, malformed matrices
  RT_INVALID_OPERATION = 0x0502,  ///< call not allowed in the current state (nesting, no context)
  RT_STACK_OVERFLOW = 0x0503,     ///< rtPushMatrix beyond RT_MAX_MATRIX_STACK_DEPTH
  RT_STACK_UNDERFLOW = 0x0504,    ///< rtPopMatrix with nothing pushed
  RT_OUT_OF_MEMORY = 0x0505,      ///< an allocation failed; the call had no effect
};

/// Creates a context with an empty scene built from `options`, identity matrix and empty stack.
/// The new context is not made current. Returns null when out of memory.
RTcontext rtCreateContext(const SceneOptions& options = {});
/// Destroys a context and its scene; null is ignored. If it is current on this thread, this
/// thread is left without a current context. It must not be current on any other thread.
void rtDestroyContext(RTcontext context);
/// Makes `context` (or none, for null) current on the calling thread.
void rtMakeCurrent(RTcontext context);
/// The calling thread's current context, or null.
RTcontext rtGetCurrentContext();

/// Returns the oldest error not yet reported on the current context (or on the thread's
/// no-context slot) and clears it; RT_NO_ERROR when there is none. As with a GL error flag, codes
/// of errors made while one is pending are not queued (their messages are still kept).
RTerror rtGetError();
/// The message of the most recent error, starting with the call's name; "" if there has been
/// none. It is not cleared by rtGetError. The pointer stays valid until the next error on the
/// same context or thread slot, or until the context is destroyed.
const char* rtGetErrorString();

/// Reserves a new object id; the object exists in the scene at once, empty (it renders nothing
/// until defined). `usage` is RT_STATIC, RT_RIGID or RT_DEFORMING and picks the accelerator
/// builder; it cannot change later. Returns RT_INVALID_ID on error (RT_INVALID_ENUM).
RTuint rtNewObject(RTenum usage = RT_STATIC);
/// Opens the definition of object `id`, replacing its mesh at rtEndObject. Rejected inside
/// another definition (which is then spoilt) and for unknown ids. Vertices are in object space:
/// the matrix stack does not apply to them. The current normal and texture coordinate reset to
/// GL's defaults, (0, 0, 1) and (0, 0).
void rtBeginObject(RTuint id);
/// Closes the open definition and hands its triangles to the scene (visible after rtCommit).
/// Fails, discarding the definition and keeping the object's previous mesh, when it is called
/// inside rtBegin/rtEnd or when an earlier call during the definition was rejected.
void rtEndObject();

/// Starts a primitive block inside an object definition. Only RT_TRIANGLES is accepted.
void rtBegin(RTenum mode);
/// Ends a primitive block; a vertex count that is not a multiple of 3 is an error.
void rtEnd();
/// Emits a vertex (object space) with the current normal and texture coordinate. Only inside
/// rtBegin/rtEnd. If any vertex of an object was emitted after an rtNormal3f (rtTexCoord2f),
/// the mesh stores a normal (texture coordinate) for every vertex.
void rtVertex3f(float x, float y, float z);
/// Sets the current normal for the following vertices; only inside an object definition.
void rtNormal3f(float x, float y, float z);
/// Sets the current texture coordinate for the following vertices; only inside a definition.
void rtTexCoord2f(float u, float v);

/// Saves a copy of the current matrix; RT_STACK_OVERFLOW beyond RT_MAX_MATRIX_STACK_DEPTH.
void rtPushMatrix();
/// Restores the last saved matrix; RT_STACK_UNDERFLOW when nothing is saved.
void rtPopMatrix();
/// Replaces the current matrix with the identity.
void rtLoadIdentity();
/// Multiplies the current matrix on the right by a translation (GL order: M = M * T).
void rtTranslatef(float x, float y, float z);
/// Multiplies the current matrix on the right by a right-handed rotation of `degrees` about the
/// axis (x, y, z), which is normalised; a zero axis gives the identity (as tg::Affine3d does).
void rtRotatef(float degrees, float x, float y, float z);
/// Multiplies the current matrix on the right by a scaling; zero factors are allowed here and
/// rejected at rtInstantiateObject.
void rtScalef(float x, float y, float z);
/// Multiplies the current matrix on the right by a column-major 4x4 matrix, as glMultMatrixf.
/// Its last row must be exactly (0, 0, 0, 1): projective matrices are rejected.
void rtMultMatrixf(const float m[16]);

/// Copies the current matrix to `m` as a column-major 4x4 (like glGetDoublev of the modelview
/// matrix); its last row is (0, 0, 0, 1).
void rtGetMatrixd(double m[16]);

/// Places object `id` in the world under the current matrix (composed in double, stored by the
/// scene as tg::Scene::createInstance does). Rejected inside an object definition, for unknown
/// ids, and for matrices that are singular or do not fit in float. Returns the instance id or
/// RT_INVALID_ID.
RTuint rtInstantiateObject(RTuint id);
/// Replaces the matrix of instance `instance` with the current matrix (the per-frame update of
/// rigid motion); same checks as rtInstantiateObject.
void rtSetInstanceMatrix(RTuint instance);

/// Builds what changed and publishes it to rtGetScene() (tg::Scene::commit). Rejected inside an
/// object definition.
void rtCommit();
/// The current context's scene, for tracing; an empty committed scene without a context.
const Scene& rtGetScene();

}  // namespace tg
