// A headless OpenGL ES 3.0 context through EGL, current on the thread that
// created it. EGL contexts are current per thread: create, use and destroy an
// EglContext on one thread (the nodelet keeps its own render thread for that).
//
// Why GLES 3.0 rather than desktop GL 3.3 core: libGLESv2 exports every GLES 3
// entry point, so no function loader is needed, and the same shaders run on
// Mesa (llvmpipe or a GPU) and on the embedded GPUs a handheld rig would carry.
#pragma once

#include <string>

namespace ar_overlay {

class EglContext {
 public:
  // Prefers Mesa's surfaceless platform (a GPU render node when there is one,
  // llvmpipe otherwise), then EGL's default display. Throws std::runtime_error
  // with the failing EGL call and its error code.
  EglContext();
  ~EglContext();
  EglContext(const EglContext&) = delete;
  EglContext& operator=(const EglContext&) = delete;

  // Makes the context current on the calling thread again.
  void MakeCurrent();
  // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)".
  const std::string& renderer() const { return renderer_; }

 private:
  void* display_ = nullptr;  // EGLDisplay
  void* context_ = nullptr;  // EGLContext
  std::string renderer_;
};

}  // namespace ar_overlay
