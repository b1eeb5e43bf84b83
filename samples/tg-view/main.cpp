// tg-view: plays a scene file, or the built-in demo, in a window.
//
//   tg-view [SCENE] [--size WxH] [--mode opengl|whitted|normals|classes|instances] [--depth D]
//           [--threads N] [--fps F] [--scale S] [--screenshot FILE.png [--frames N]]
//
// Every frame goes the way of tg-render (SceneGraph::advanceTo, sync, SceneRenderer::update,
// render) and the beauty image is shown as a texture over the whole window.
//
// Mouse: left drag orbits, right or middle drag pans, the wheel zooms; the first drag takes the
// view over from the scene's camera ('c' gives it back). Keys: space play/pause, right/left
// arrow step one frame, 1-5 shading mode, t mip-mapped textures on/off, +/- render
// resolution, Esc or q quit.
//
// Exit codes: 0 success, 1 bad input (the message names the file) or no window, 2 bad usage.
#include <GLFW/glfw3.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>

#include "GlDisplay.h"
#include "OrbitCamera.h"
#include "ToolThreads.h"
#include "ViewOptions.h"
#include "tracegraph/backend/Error.h"
#include "tracegraph/backend/render/ImageIO.h"
#include "tracegraph/loaders/SceneSource.h"
#include "tracegraph/scenegraph/SceneGraph.h"
#include "tracegraph/scenegraph/SceneRenderer.h"

using namespace tg;
using namespace tg::view_tool;

namespace {

using Clock = std::chrono::steady_clock;

constexpr double kMinScale = 0.0625;

/// The animation's frames as a loop: stepping moves by whole frames, playing by wall time.
struct Playback {
  SceneTiming timing;
  double frameDt = 1.0 / 30.0;  ///< seconds between frames
  double period = 0.0;          ///< seconds before the loop repeats; 0: no animation
  double time = 0.0;
  bool playing = false;

  Playback(const SceneTiming& t, double fps) : timing(t), time(t.start) {
    if (timing.frames > 1) {
      frameDt = (timing.end - timing.start) / (timing.frames - 1);
      // The frame after the last is the first again, one frame interval later.
      period = timing.end - timing.start + frameDt;
      playing = period > 0.0;
    } else {
      frameDt = 1.0 / fps;
    }
  }
  int frameIndex() const {
    if (timing.frames <= 1 || frameDt <= 0.0) return 0;
    const int f = static_cast<int>(std::floor((time - timing.start) / frameDt + 0.5));
    return ((f % timing.frames) + timing.frames) % timing.frames;
  }
  void advance(double seconds) {
    if (!playing || period <= 0.0) return;
    time = timing.start + std::fmod(time - timing.start + seconds, period);
  }
  void step(int frames) {
    playing = false;
    if (timing.frames <= 1) return;
    const int f = ((frameIndex() + frames) % timing.frames + timing.frames) % timing.frames;
    time = timing.timeOf(f);
  }
};

/// Frame costs summed over the title's update interval.
struct TitleStats {
  int frames = 0;
  double rays = 0.0, renderMs = 0.0, syncMs = 0.0, rebuildMs = 0.0, toplevelMs = 0.0;
  Clock::time_point since = Clock::now();

  void add(const FrameStats& s) {
    ++frames;
    rays += static_cast<double>(s.rays.total());
    renderMs += s.renderMs;
    syncMs += s.syncMs;
    rebuildMs += s.rebuildMs;
    toplevelMs += s.toplevelMs;
  }
};

/// Everything the GLFW callbacks change, reached through the window's user pointer.
struct Viewer {
  const ViewOptions& options;
  SceneGraph graph;
  SceneRenderer renderer;
  RenderSettings settings;
  Playback playback;
  OrbitCamera orbit;
  Camera lastCamera = Camera(CameraParams{});  ///< what the last frame was rendered with
  double scale = 1.0;
  bool changed = true;  ///< something other than the clock asks for a new frame
  int dragButton = -1;
  double cursorX = 0.0, cursorY = 0.0;
  std::string name;

  Viewer(const ViewOptions& o, const SceneSource& source)
      : options(o),
        graph(SyncOptions{.scene = sceneOptionsFor(o.engine)}),
        renderer(graph),
        playback(source.timing, o.fps),
        scale(o.scale),
        name(source.name) {
    settings.mode = o.mode;
    settings.maxDepth = o.depth;
    settings.aovs = false;  // the window shows the beauty image only
    renderer.setSettings(settings);
    renderer.setLook(source.look);
    renderer.setTextureSearchPath(source.textureFolders);
    graph.setRoot(source.root);
  }

  void setMode(RenderMode mode) {
    settings.mode = mode;
    renderer.setSettings(settings);
    changed = true;
  }
  /// Switches textures between bilinear and mip-mapped (trilinear) lookups.
  void toggleMipMaps() {
    settings.textureFilter = settings.textureFilter == TextureFilter::Trilinear
                                 ? TextureFilter::Bilinear
                                 : TextureFilter::Trilinear;
    renderer.setSettings(settings);
    changed = true;
  }
  void takeOverCamera() {
    if (!orbit.active()) orbit.takeOver(lastCamera, graph.backendScene().bounds());
  }
};

Viewer& viewerOf(GLFWwindow* window) {
  return *static_cast<Viewer*>(glfwGetWindowUserPointer(window));
}

void onKey(GLFWwindow* window, int key, int /*scancode*/, int action, int /*mods*/) {
  if (action != GLFW_PRESS && action != GLFW_REPEAT) return;
  Viewer& v = viewerOf(window);
  switch (key) {
    case GLFW_KEY_ESCAPE:
      glfwSetWindowShouldClose(window, GLFW_TRUE);
      break;
    case GLFW_KEY_SPACE:
      if (action == GLFW_PRESS) v.playback.playing = !v.playback.playing && v.playback.period > 0;
      break;
    case GLFW_KEY_RIGHT:
      v.playback.step(1);
      v.changed = true;
      break;
    case GLFW_KEY_LEFT:
      v.playback.step(-1);
      v.changed = true;
      break;
    case GLFW_KEY_KP_ADD:
      v.scale = std::min(1.0, v.scale * 2.0);
      v.changed = true;
      break;
    case GLFW_KEY_KP_SUBTRACT:
      v.scale = std::max(kMinScale, v.scale / 2.0);
      v.changed = true;
      break;
    default:
      break;
  }
}

// Characters rather than key codes for what is printed on the key, so that q, + and the digits
// work on any keyboard layout.
void onChar(GLFWwindow* window, unsigned int codepoint) {
  Viewer& v = viewerOf(window);
  switch (codepoint) {
    case 'q':
    case 'Q':
      glfwSetWindowShouldClose(window, GLFW_TRUE);
      break;
    case '1':
      v.setMode(RenderMode::OpenGL);
      break;
    case '2':
      v.setMode(RenderMode::Whitted);
      break;
    case '3':
      v.setMode(RenderMode::Normals);
      break;
    case '4':
      v.setMode(RenderMode::Classes);
      break;
    case '5':
      v.setMode(RenderMode::Instances);
      break;
    case '+':
    case '=':
      v.scale = std::min(1.0, v.scale * 2.0);
      v.changed = true;
      break;
    case '-':
      v.scale = std::max(kMinScale, v.scale / 2.0);
      v.changed = true;
      break;
    case 'c':
    case 'C':
      v.orbit = OrbitCamera{};
      v.changed = true;
      break;
    case 't':
    case 'T':
      v.toggleMipMaps();
      break;
    default:
      break;
  }
}

void onMouseButton(GLFWwindow* window, int button, int action, int /*mods*/) {
  Viewer& v = viewerOf(window);
  if (action == GLFW_PRESS && v.dragButton < 0) {
    v.dragButton = button;
    glfwGetCursorPos(window, &v.cursorX, &v.cursorY);
  } else if (action == GLFW_RELEASE && button == v.dragButton) {
    v.dragButton = -1;
  }
}

void onCursor(GLFWwindow* window, double x, double y) {
  Viewer& v = viewerOf(window);
  const double dx = x - v.cursorX, dy = y - v.cursorY;
  v.cursorX = x;
  v.cursorY = y;
  if (v.dragButton < 0 || (dx == 0.0 && dy == 0.0)) return;
  int width = 0, height = 0;
  glfwGetWindowSize(window, &width, &height);
  v.takeOverCamera();
  if (v.dragButton == GLFW_MOUSE_BUTTON_LEFT)
    v.orbit.orbit(dx, dy, height);
  else
    v.orbit.pan(dx, dy, height);
  v.changed = true;
}

void onScroll(GLFWwindow* window, double /*dx*/, double dy) {
  Viewer& v = viewerOf(window);
  v.takeOverCamera();
  v.orbit.zoom(dy);
  v.changed = true;
}

void onFramebufferSize(GLFWwindow* window, int /*width*/, int /*height*/) {
  viewerOf(window).changed = true;
}

void onGlfwError(int code, const char* description) {
  std::cerr << "tg-view: GLFW error " << code << ": " << description << "\n";
}

std::string title(const Viewer& v, const TitleStats& s, double seconds, std::uint32_t width,
                  std::uint32_t height) {
  const double n = std::max(s.frames, 1);
  char text[512];
  std::snprintf(text, sizeof text,
                "tg-view - %s | %.1f fps | %.1f Mrays/s | sync %.2f ms (build %.2f, top %.2f) "
                "trace %.1f ms | %s%s %ux%u | frame %d%s",
                v.name.c_str(), s.frames / seconds,
                s.renderMs > 0.0 ? s.rays / (s.renderMs * 1e3) : 0.0, s.syncMs / n, s.rebuildMs / n,
                s.toplevelMs / n, s.renderMs / n,
                std::string(renderModeName(v.settings.mode)).c_str(),
                v.settings.textureFilter == TextureFilter::Trilinear ? " mip-mapped" : "", width,
                height, v.playback.frameIndex(), v.playback.playing ? "" : " (paused)");
  return text;
}

/// Opens the window and runs the frame loop until the window closes or the screenshot is saved.
int runWindow(Viewer& v, std::uint32_t width, std::uint32_t height) {
  const bool screenshot = !v.options.screenshot.empty();
  glfwSetErrorCallback(onGlfwError);
  if (!glfwInit()) {
    std::cerr << "tg-view: cannot initialise GLFW (no display? try xvfb-run)\n";
    return kBadInput;
  }
  // Any context version will do: GlDisplay uses OpenGL 1.1 only.
  glfwWindowHint(GLFW_RESIZABLE, screenshot ? GLFW_FALSE : GLFW_TRUE);
  GLFWwindow* window = glfwCreateWindow(static_cast<int>(width), static_cast<int>(height),
                                        "tg-view", nullptr, nullptr);
  if (!window) {
    std::cerr << "tg-view: cannot open a " << width << "x" << height << " OpenGL window\n";
    glfwTerminate();
    return kBadInput;
  }
  glfwMakeContextCurrent(window);
  // No vsync: the frame rate in the title is what the renderer achieves.
  glfwSwapInterval(0);
  glfwSetWindowUserPointer(window, &v);
  glfwSetKeyCallback(window, onKey);
  glfwSetCharCallback(window, onChar);
  glfwSetMouseButtonCallback(window, onMouseButton);
  glfwSetCursorPosCallback(window, onCursor);
  glfwSetScrollCallback(window, onScroll);
  glfwSetFramebufferSizeCallback(window, onFramebufferSize);

  int code = kSuccess;
  {
    GlDisplay display;
    TitleStats titleStats;
    Frame frame;
    auto last = Clock::now();
    int rendered = 0;
    try {
      while (!glfwWindowShouldClose(window)) {
        // Without animation or input there is nothing new to show: sleep until an event.
        if (!screenshot && !v.playback.playing && !v.changed)
          glfwWaitEvents();
        else
          glfwPollEvents();
        const auto now = Clock::now();
        const double wall = std::chrono::duration<double>(now - last).count();
        last = now;
        int fbWidth = 0, fbHeight = 0;
        glfwGetFramebufferSize(window, &fbWidth, &fbHeight);
        if (fbWidth <= 0 || fbHeight <= 0) continue;  // minimised
        if (!screenshot && !v.playback.playing && !v.changed) continue;
        v.changed = false;

        if (screenshot)
          v.playback.time = v.playback.timing.timeOf(rendered % v.playback.timing.frames);
        else
          v.playback.advance(wall);
        const auto w = static_cast<std::uint32_t>(std::max(1L, std::lround(fbWidth * v.scale)));
        const auto h = static_cast<std::uint32_t>(std::max(1L, std::lround(fbHeight * v.scale)));

        v.graph.advanceTo(v.playback.time);
        FrameStats stats = v.graph.sync();
        v.renderer.update();
        v.lastCamera = v.orbit.active() ? v.orbit.camera(w, h) : v.renderer.camera(w, h);
        v.renderer.render(v.lastCamera, frame, &stats);
        display.upload(frame.beauty);
        display.draw(fbWidth, fbHeight);
        ++rendered;
        titleStats.add(stats);

        if (screenshot && rendered >= v.options.frames) {
          writePng(GlDisplay::readBack(fbWidth, fbHeight), v.options.screenshot,
                   PngEncoding::Linear);
          glfwSwapBuffers(window);
          std::cerr << "tg-view: " << v.name << ", " << rendered << " frame"
                    << (rendered == 1 ? "" : "s") << ", wrote " << v.options.screenshot << "\n";
          break;
        }
        glfwSwapBuffers(window);

        const double since = std::chrono::duration<double>(now - titleStats.since).count();
        if (since >= 0.5) {
          glfwSetWindowTitle(window, title(v, titleStats, since, w, h).c_str());
          titleStats = TitleStats{};
        }
      }
    } catch (const std::exception& e) {
      // tg::Error names the file (a texture, the screenshot); anything else is still reported
      // rather than a crash.
      std::cerr << "tg-view: " << e.what() << "\n";
      code = kBadInput;
    }
  }
  glfwDestroyWindow(window);
  glfwTerminate();
  return code;
}

int run(const ViewOptions& o) {
  SceneSource source;
  try {
    source = loadSceneSource(o.scene, o.fps);
  } catch (const Error& e) {
    std::cerr << "tg-view: " << e.what() << "\n";
    return kBadInput;
  }
  for (const std::string& w : source.warnings) std::cerr << "tg-view: warning: " << w << "\n";
  std::uint32_t width = o.width, height = o.height;
  if (!o.sizeGiven && source.resolution) std::tie(width, height) = *source.resolution;
  Viewer viewer(o, source);
  const int code = runWindow(viewer, width, height);
  for (const std::string& w : viewer.renderer.warnings())
    std::cerr << "tg-view: warning: " << w << "\n";
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  const auto parsed = parseViewOptions(argc, argv);
  if (const int* code = std::get_if<int>(&parsed)) return *code;
  const ViewOptions& o = std::get<ViewOptions>(parsed);
  // The arena runs `run` on this (the main) thread, as GLFW requires.
  return tools::runWithThreads(o.threads, [&] { return run(o); });
}
