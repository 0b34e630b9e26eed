// A headless OpenGL 4.5 core context through EGL: no window system, no surface. Rendering goes
// into framebuffer objects. The same binary uses the NVIDIA driver on a GPU machine and Mesa's
// llvmpipe on a CPU-only one; glvnd picks the vendor library at run time.
//
// Displays are tried in this order, the first that yields a 4.5 core context wins:
//   1. the EGL device platform (EGL_EXT_platform_device), hardware devices before software
//      ones (a device listing EGL_MESA_device_software is llvmpipe);
//   2. Mesa's surfaceless platform (EGL_MESA_platform_surfaceless);
//   3. eglGetDisplay(EGL_DEFAULT_DISPLAY).
#pragma once

#include <cstddef>
#include <string>

namespace sss {

class GlContext {
 public:
  // Creates the context and makes it current on this thread. Throws Error when no display
  // gives an OpenGL 4.5 core context; the message lists what each attempt answered.
  GlContext();
  ~GlContext();
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  // Which display was taken, e.g. "EGL device platform, device 0 (software: ...)".
  const std::string& eglPath() const { return eglPath_; }
  const std::string& eglVendor() const { return eglVendor_; }
  const std::string& glVendor() const { return glVendor_; }
  const std::string& glRenderer() const { return glRenderer_; }
  const std::string& glVersion() const { return glVersion_; }
  int maxSamples() const { return maxSamples_; }
  // currentMaxVertexStorageBytes() of this context.
  std::size_t maxVertexStorageBytes() const { return maxVertexStorageBytes_; }
  // True on a software rasterizer (llvmpipe, softpipe), where GL timer queries do not measure
  // the work that the CPU does.
  bool isSoftware() const { return software_; }

 private:
  void* display_ = nullptr;
  void* context_ = nullptr;
  std::string eglPath_, eglVendor_, glVendor_, glRenderer_, glVersion_;
  int maxSamples_ = 1;
  std::size_t maxVertexStorageBytes_ = 0;
  bool software_ = false;
};

// The largest storage buffer a vertex shader of the current context may read, in bytes: 0 where
// vertex shaders read none (GL 4.3 requires them of compute and fragment shaders only).
std::size_t currentMaxVertexStorageBytes();

}  // namespace sss
