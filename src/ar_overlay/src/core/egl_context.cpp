#include "ar_overlay/core/egl_context.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GLES3/gl3.h>

#include <cstdio>
#include <stdexcept>

namespace ar_overlay {
namespace {

[[noreturn]] void Fail(const char* call) {
  char code[16];
  std::snprintf(code, sizeof(code), "0x%04x", static_cast<unsigned>(eglGetError()));
  throw std::runtime_error(std::string("EGL: ") + call + " failed (error " + code + ")");
}

EGLDisplay OpenDisplay() {
  auto get_platform_display =
      reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (get_platform_display != nullptr) {
    EGLDisplay d = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (d != EGL_NO_DISPLAY && eglInitialize(d, nullptr, nullptr)) return d;
  }
  EGLDisplay d = eglGetDisplay(EGL_DEFAULT_DISPLAY);
  if (d == EGL_NO_DISPLAY || !eglInitialize(d, nullptr, nullptr)) Fail("eglInitialize");
  return d;
}

}  // namespace

EglContext::EglContext() {
  // The display stays initialised for the process: eglTerminate would pull it
  // from under other contexts (another nodelet, another test) using it.
  EGLDisplay display = OpenDisplay();
  if (!eglBindAPI(EGL_OPENGL_ES_API)) Fail("eglBindAPI(EGL_OPENGL_ES_API)");
  // The default EGL_SURFACE_TYPE is a window, which a surfaceless display has none of.
  const EGLint config_attribs[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_ES3_BIT,
                                   EGL_NONE};
  EGLConfig config = nullptr;
  EGLint n = 0;
  if (!eglChooseConfig(display, config_attribs, &config, 1, &n) || n < 1) Fail("eglChooseConfig(ES3)");
  const EGLint context_attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 0, EGL_NONE};
  EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, context_attribs);
  if (context == EGL_NO_CONTEXT) Fail("eglCreateContext(GLES 3.0)");
  display_ = display;
  context_ = context;
  MakeCurrent();  // surfaceless: we draw into our own framebuffer object
  const GLubyte* name = glGetString(GL_RENDERER);
  renderer_ = name ? reinterpret_cast<const char*>(name) : "unknown";
}

EglContext::~EglContext() {
  eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(display_, context_);
}

void EglContext::MakeCurrent() {
  if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_)) Fail("eglMakeCurrent(surfaceless)");
}

}  // namespace ar_overlay
