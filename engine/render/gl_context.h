// Where OpenGL 3.3 core draws: an OSMesa off-screen context (headless tests, video export) or a GLFW window
// (the interactive viewer). The renderer draws into its own framebuffer objects either way, so the drawing
// code is the same; a window only adds the final blit to its back buffer (FaceRenderer::present).
//
//   th::render::OffscreenContext context;                 // throws th::Error if OSMesa has no 3.3 core
//   context th::render::FaceRenderer renderer(context, mesh);
//   ...
//   th::render::WindowContext window({.width = 1280, .height = 720});   // throws th::Error without a display
//   while (!window.shouldClose()) { renderer.render(camera); renderer.present(window.framebufferSize());
//   window.swapBuffers(); window.pollEvents(); }
//
// Thread contract: a context belongs to one thread: create it, make it current, draw with it and destroy it
// there (GLFW further wants its windows on the main thread). The GL entry points (glad) are process-wide:
// they are loaded when a context of the other kind becomes current, so the two kinds can live in one process
// but not be current on two threads at once.
#pragma once

#include <string>
#include <utility>
#include <vector>

struct GLFWwindow;

namespace th::render {

class GlContext {
 public:
  GlContext() = default;
  virtual ~GlContext() = default;
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  // Binds the context to the calling thread (and loads the GL entry points if another kind was loaded).
  virtual void makeCurrent() = 0;
  // "osmesa" or "glfw".
  virtual const char* kind() const = 0;
  // GL_RENDERER and GL_VERSION, e.g. "llvmpipe (LLVM 15.0.6, 256 bits), 4.5 (Core Profile) Mesa 22.3.6";
  // makes the context current.
  std::string description();
};

// An OSMesa context with a default framebuffer of its own (colour and depth), 16 x 16 unless asked: the renderer
// draws into framebuffer objects of any size, so the context does not depend on the image size. A larger one
// stands in for a window's (benchmarks of renderToWindow).
class OffscreenContext final : public GlContext {
 public:
  // Created current; throws th::Error if OSMesa cannot give a 3.3 core context.
  explicit OffscreenContext(int framebufferWidth = 16, int framebufferHeight = 16);
  ~OffscreenContext() override;

  void makeCurrent() override;
  const char* kind() const override { return "osmesa"; }

 private:
  void* context_ = nullptr;  // OSMesaContext
  int width_ = 16;
  int height_ = 16;
  std::vector<unsigned char> buffer_;  // the default framebuffer, RGBA
};

struct WindowOptions {
  int width = 1280;
  int height = 720;
  std::string title = "talkinghead";
  bool visible = true;
  bool vsync = true;   // swapBuffers waits for the display's refresh
  bool depth = false;  // a depth buffer of its own (FaceRenderer::renderToWindow draws into the window)
};

// A GLFW window with a 3.3 core context (no multisampling of its own: the renderer resolves its own MSAA
// target into the window's back buffer).
class WindowContext final : public GlContext {
 public:
  // Created current. Throws th::Error when there is no display (DISPLAY / WAYLAND_DISPLAY unset, or GLFW
  // cannot connect to it) or the driver has no 3.3 core context.
  explicit WindowContext(const WindowOptions& options = {});
  ~WindowContext() override;

  void makeCurrent() override;
  const char* kind() const override { return "glfw"; }

  GLFWwindow* window() const { return window_; }  // for input callbacks
  bool shouldClose() const;
  std::pair<int, int> framebufferSize() const;  // in pixels (may differ from the window size on HiDPI)
  void swapBuffers();
  void pollEvents();

 private:
  void release();  // destroys the window and, with the last window, GLFW

  GLFWwindow* window_ = nullptr;
  bool initialised_ = false;  // this window counts as a GLFW user
};

}  // namespace th::render
