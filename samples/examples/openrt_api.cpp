// example-openrt-api: the backend on its own, through the OpenRT-style immediate-mode API.
//
// One object (a unit quad facing +z, two triangles) is defined like a display list, placed
// three times with the GL-like matrix stack, committed, and traced with a few rays; then one
// instance is moved (the per-frame update of a rigid object) and the rays are traced again.
// Finally a call in the wrong state shows how errors are reported: recorded, never thrown.
//
// Exits 1 when a ray hits something other than what was placed in its way.
#include <tracegraph/tracegraph.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>

using namespace tg;

namespace {

int failures = 0;

void expect(bool ok, const std::string& what) {
  if (!ok) {
    std::cerr << "example-openrt-api: FAILED: " << what << "\n";
    ++failures;
  }
}

/// Traces a ray along -z from (x, y, 10) and prints the hit; returns the instance hit, or
/// RT_INVALID_ID.
RTuint traceDown(float x, float y) {
  Ray ray;
  ray.origin = {x, y, 10.0f};
  ray.direction = {0.0f, 0.0f, -1.0f};
  Hit hit;
  if (!rtGetScene().intersect(ray, hit)) {
    std::printf("  ray at (%5.2f, %5.2f): miss\n", static_cast<double>(x), static_cast<double>(y));
    return RT_INVALID_ID;
  }
  std::printf(
      "  ray at (%5.2f, %5.2f): instance %u, triangle %u, t = %.4f, normal (%.2f, %.2f, "
      "%.2f)\n",
      static_cast<double>(x), static_cast<double>(y), hit.instanceId, hit.primId,
      static_cast<double>(hit.t), static_cast<double>(hit.geometricNormal.x),
      static_cast<double>(hit.geometricNormal.y), static_cast<double>(hit.geometricNormal.z));
  return hit.instanceId;
}

}  // namespace

int main() {
  RTcontext context = rtCreateContext();
  if (!context) {
    std::cerr << "example-openrt-api: cannot create a context\n";
    return 1;
  }
  rtMakeCurrent(context);

  // The object: a unit quad in the z = 0 plane, in object space (the matrix stack does not
  // apply to vertices, only to instances).
  const RTuint quad = rtNewObject(RT_RIGID);
  rtBeginObject(quad);
  rtBegin(RT_TRIANGLES);
  rtNormal3f(0.0f, 0.0f, 1.0f);
  rtVertex3f(-0.5f, -0.5f, 0.0f);
  rtVertex3f(0.5f, -0.5f, 0.0f);
  rtVertex3f(0.5f, 0.5f, 0.0f);
  rtVertex3f(-0.5f, -0.5f, 0.0f);
  rtVertex3f(0.5f, 0.5f, 0.0f);
  rtVertex3f(-0.5f, 0.5f, 0.0f);
  rtEnd();
  rtEndObject();

  // Three instances: left at z = 0, middle lifted to z = 1 and turned 45 degrees about z,
  // right at z = -1 and scaled by 2.
  RTuint instances[3];
  rtPushMatrix();
  rtTranslatef(-2.0f, 0.0f, 0.0f);
  instances[0] = rtInstantiateObject(quad);
  rtPopMatrix();
  rtPushMatrix();
  rtTranslatef(0.0f, 0.0f, 1.0f);
  rtRotatef(45.0f, 0.0f, 0.0f, 1.0f);
  instances[1] = rtInstantiateObject(quad);
  rtPopMatrix();
  rtPushMatrix();
  rtTranslatef(2.0f, 0.0f, -1.0f);
  rtScalef(2.0f, 2.0f, 2.0f);
  instances[2] = rtInstantiateObject(quad);
  rtPopMatrix();
  rtCommit();
  if (rtGetError() != RT_NO_ERROR) {
    std::cerr << "example-openrt-api: " << rtGetErrorString() << "\n";
    return 1;
  }
  std::printf("object %u, instances %u %u %u, %zu triangles instanced\n", quad, instances[0],
              instances[1], instances[2], rtGetScene().instancedTriangleCount());

  std::printf("first frame:\n");
  expect(traceDown(-2.0f, 0.0f) == instances[0], "the left quad is hit");
  expect(traceDown(0.0f, 0.65f) == instances[1], "the turned quad reaches y = 0.65");
  expect(traceDown(0.45f, 0.45f) == RT_INVALID_ID, "the turned quad's corner is gone");
  expect(traceDown(2.9f, 0.9f) == instances[2], "the scaled quad reaches (2.9, 0.9)");
  expect(traceDown(5.0f, 0.0f) == RT_INVALID_ID, "nothing right of the scaled quad");
  {
    // t through the middle instance: from z = 10 down to its plane at z = 1.
    Ray ray;
    ray.origin = {0.0f, 0.0f, 10.0f};
    ray.direction = {0.0f, 0.0f, -1.0f};
    Hit hit;
    expect(rtGetScene().intersect(ray, hit) && std::abs(hit.t - 9.0f) < 1e-5f,
           "the lifted quad is hit at t = 9");
  }

  // Next frame: the middle instance moves to x = 4 (only its matrix changes).
  rtLoadIdentity();
  rtTranslatef(4.0f, 0.0f, 1.0f);
  rtSetInstanceMatrix(instances[1]);
  rtLoadIdentity();
  rtCommit();
  std::printf("after moving instance %u:\n", instances[1]);
  expect(traceDown(0.0f, 0.0f) == RT_INVALID_ID, "the middle quad has left x = 0");
  expect(traceDown(4.0f, 0.0f) == instances[1], "the middle quad is at x = 4");

  // Errors are recorded, not thrown: a vertex outside rtBegin/rtEnd is rejected and leaves the
  // scene as it was.
  rtVertex3f(0.0f, 0.0f, 0.0f);
  const RTerror error = rtGetError();
  std::printf("misplaced rtVertex3f: error 0x%04x, \"%s\"\n", static_cast<unsigned>(error),
              rtGetErrorString());
  expect(error == RT_INVALID_OPERATION, "rtVertex3f outside rtBegin is an invalid operation");
  expect(rtGetError() == RT_NO_ERROR, "rtGetError clears the error");

  rtMakeCurrent(nullptr);
  rtDestroyContext(context);
  if (failures == 0) std::cout << "OK: every ray hit what was placed in its way\n";
  return failures == 0 ? 0 : 1;
}
