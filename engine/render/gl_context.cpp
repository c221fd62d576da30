#include "render/gl_context.h"

// glad first: it stands in for <GL/gl.h>, which osmesa.h would otherwise pull in.
#include <glad/gl.h>
#define GLFW_INCLUDE_NONE
#include <GL/osmesa.h>
#include <GLFW/glfw3.h>
#include <dlfcn.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <mutex>
#include <string>
#include <type_traits>

#include "core/error.h"

namespace th::render {
namespace {

// Which loader the process-wide glad pointers came from: 0 none, 1 OSMesa, 2 GLFW.
std::atomic<int> loadedKind{0};

void loadEntryPoints(int kind, GLADloadfunc loader, const char* what) {
  if (loadedKind.load() == kind) return;
  const int version = gladLoadGL(loader);
  if (version == 0) throw Error(std::string(what) + ": could not load the OpenGL entry points");
  if (GLAD_VERSION_MAJOR(version) * 10 + GLAD_VERSION_MINOR(version) < 33)
    throw Error(std::string(what) + ": OpenGL 3.3 core is needed, the context has " +
                std::to_string(GLAD_VERSION_MAJOR(version)) + "." + std::to_string(GLAD_VERSION_MINOR(version)));
  loadedKind.store(kind);
}

// OSMesa, opened the first time an off-screen context is made, not linked: it brings LLVM (llvmpipe) with it,
// whose loading every process would otherwise pay at start, drawing or not (a tenth of a second of the CLI's
// start here). TALKINGHEAD_OSMESA_LIBRARY is its SONAME, read from the library at configure time.
struct OsMesa {
  decltype(&::OSMesaCreateContextAttribs) createContextAttribs = nullptr;
  decltype(&::OSMesaDestroyContext) destroyContext = nullptr;
  decltype(&::OSMesaMakeCurrent) makeCurrent = nullptr;
  decltype(&::OSMesaGetCurrentContext) getCurrentContext = nullptr;
  decltype(&::OSMesaGetProcAddress) getProcAddress = nullptr;
};

const OsMesa& osMesa() {
  static const OsMesa functions = [] {
    // Never closed: contexts and the GL entry points glad keeps point into it until the process ends.
    void* library = dlopen(TALKINGHEAD_OSMESA_LIBRARY, RTLD_NOW | RTLD_LOCAL);
    if (library == nullptr) {
      const char* reason = dlerror();
      throw Error(std::string("OSMesa: cannot load ") + TALKINGHEAD_OSMESA_LIBRARY + " (" +
                  (reason != nullptr ? reason : "unknown error") + "); Debian's libosmesa6 provides it");
    }
    OsMesa loaded;
    const auto find = [library](auto& function, const char* name) {
      function = reinterpret_cast<std::remove_reference_t<decltype(function)>>(dlsym(library, name));
      if (function == nullptr) throw Error(std::string("OSMesa: ") + TALKINGHEAD_OSMESA_LIBRARY + " has no " + name);
    };
    find(loaded.createContextAttribs, "OSMesaCreateContextAttribs");
    find(loaded.destroyContext, "OSMesaDestroyContext");
    find(loaded.makeCurrent, "OSMesaMakeCurrent");
    find(loaded.getCurrentContext, "OSMesaGetCurrentContext");
    find(loaded.getProcAddress, "OSMesaGetProcAddress");
    return loaded;
  }();
  return functions;
}

GLADapiproc osmesaProc(const char* name) {
  return reinterpret_cast<GLADapiproc>(osMesa().getProcAddress(name));
}
GLADapiproc glfwProc(const char* name) {
  return reinterpret_cast<GLADapiproc>(glfwGetProcAddress(name));
}

// GLFW reports errors through a callback; the last one is kept for the exception's text.
std::mutex glfwErrorMutex;
std::string glfwLastError;
int glfwUsers = 0;  // windows alive: glfwTerminate when the last goes (guarded by glfwErrorMutex)

void onGlfwError(int /*code*/, const char* description) {
  std::lock_guard lock(glfwErrorMutex);
  glfwLastError = description != nullptr ? description : "unknown error";
}

std::string takeGlfwError() {
  std::lock_guard lock(glfwErrorMutex);
  std::string message = glfwLastError.empty() ? "unknown error" : glfwLastError;
  glfwLastError.clear();
  for (char& c : message)
    if (c == '\n') c = ' ';
  return message;
}

bool hasDisplay() {
  const char* x11 = std::getenv("DISPLAY");
  const char* wayland = std::getenv("WAYLAND_DISPLAY");
  return (x11 != nullptr && *x11 != '\0') || (wayland != nullptr && *wayland != '\0');
}

}  // namespace

std::string GlContext::description() {
  makeCurrent();
  const auto text = [](GLenum name) {
    const GLubyte* s = glGetString(name);
    return s != nullptr ? std::string(reinterpret_cast<const char*>(s)) : std::string("?");
  };
  return text(GL_RENDERER) + ", " + text(GL_VERSION);
}

// ---- OSMesa ----

OffscreenContext::OffscreenContext(int framebufferWidth, int framebufferHeight)
    : width_(framebufferWidth),
      height_(framebufferHeight),
      buffer_(static_cast<std::size_t>(std::max(framebufferWidth, 1)) *
              static_cast<std::size_t>(std::max(framebufferHeight, 1)) * 4) {
  if (framebufferWidth <= 0 || framebufferHeight <= 0)
    throw Error("OSMesa: the default framebuffer's size must be positive, not " + std::to_string(framebufferWidth) +
                "x" + std::to_string(framebufferHeight));
  const int attributes[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS,
                            24,  // for renderToWindow() into the default framebuffer (the renderers'
                                 // framebuffer objects have depth buffers of their own)
                            OSMESA_PROFILE, OSMESA_CORE_PROFILE, OSMESA_CONTEXT_MAJOR_VERSION, 3,
                            OSMESA_CONTEXT_MINOR_VERSION, 3, 0};
  OSMesaContext context = osMesa().createContextAttribs(attributes, nullptr);
  if (context == nullptr) throw Error("OSMesa: could not create an OpenGL 3.3 core off-screen context");
  context_ = context;
  try {
    makeCurrent();
  } catch (...) {
    osMesa().destroyContext(context);
    throw;
  }
}

OffscreenContext::~OffscreenContext() {
  OSMesaContext context = static_cast<OSMesaContext>(context_);
  const OsMesa& mesa = osMesa();
  if (mesa.getCurrentContext() == context) mesa.makeCurrent(nullptr, nullptr, 0, 0, 0);
  mesa.destroyContext(context);
}

void OffscreenContext::makeCurrent() {
  if (osMesa().makeCurrent(static_cast<OSMesaContext>(context_), buffer_.data(), GL_UNSIGNED_BYTE, width_, height_) ==
      0)
    throw Error("OSMesa: could not make the off-screen context current");
  loadEntryPoints(1, osmesaProc, "OSMesa");
}

// ---- GLFW ----

WindowContext::WindowContext(const WindowOptions& options) {
  // GLFW without a display prints to stderr or, with some builds, aborts in the platform layer; say it
  // plainly.
  if (!hasDisplay())
    throw Error(
        "cannot open a window: no display (DISPLAY and WAYLAND_DISPLAY are unset); render off-screen "
        "instead");
  {
    std::lock_guard lock(glfwErrorMutex);
    glfwSetErrorCallback(onGlfwError);
  }
  if (glfwInit() == GLFW_FALSE) throw Error("cannot open a window: " + takeGlfwError());
  {
    std::lock_guard lock(glfwErrorMutex);
    ++glfwUsers;
    initialised_ = true;
  }
  glfwDefaultWindowHints();
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_SAMPLES, 0);
  glfwWindowHint(GLFW_DEPTH_BITS, options.depth ? 24 : 0);
  glfwWindowHint(GLFW_VISIBLE, options.visible ? GLFW_TRUE : GLFW_FALSE);
  window_ = glfwCreateWindow(options.width, options.height, options.title.c_str(), nullptr, nullptr);
  if (window_ == nullptr) {
    const std::string message = takeGlfwError();
    release();
    throw Error("cannot open a window: " + message);
  }
  try {
    makeCurrent();
  } catch (...) {
    release();
    throw;
  }
  glfwSwapInterval(options.vsync ? 1 : 0);
}

WindowContext::~WindowContext() {
  release();
}

void WindowContext::release() {
  if (window_ != nullptr) {
    glfwDestroyWindow(window_);
    window_ = nullptr;
  }
  if (!initialised_) return;
  initialised_ = false;
  std::lock_guard lock(glfwErrorMutex);
  if (--glfwUsers == 0) {
    glfwTerminate();
    if (loadedKind.load() == 2) loadedKind.store(0);
  }
}

void WindowContext::makeCurrent() {
  glfwMakeContextCurrent(window_);
  loadEntryPoints(2, glfwProc, "GLFW");
}

bool WindowContext::shouldClose() const {
  return glfwWindowShouldClose(window_) != 0;
}

std::pair<int, int> WindowContext::framebufferSize() const {
  int width = 0;
  int height = 0;
  glfwGetFramebufferSize(window_, &width, &height);
  return {width, height};
}

void WindowContext::swapBuffers() {
  glfwSwapBuffers(window_);
}

void WindowContext::pollEvents() {
  glfwPollEvents();
}

}  // namespace th::render
