#include "render/gl_context.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include "core/error.h"
#include "render/gl.h"

namespace sss {
namespace {

std::string eglErrorName(EGLint code) {
  switch (code) {
    case EGL_SUCCESS:
      return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED:
      return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS:
      return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC:
      return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE:
      return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG:
      return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT:
      return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY:
      return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH:
      return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER:
      return "EGL_BAD_PARAMETER";
    default:
      return "EGL error " + std::to_string(code);
  }
}

bool hasExtension(const char* list, const char* name) {
  if (!list) return false;
  const std::size_t n = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)); p += n) {
    if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
  }
  return false;
}

struct Candidate {
  std::string label;
  std::function<EGLDisplay()> open;
};

// The displays to try, in the order of gl_context.h: device platform (hardware first), Mesa's
// surfaceless platform, the default display.
std::vector<Candidate> displayCandidates() {
  const char* clientExtensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  auto getPlatformDisplay = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
      eglGetProcAddress("eglGetPlatformDisplayEXT"));

  std::vector<Candidate> candidates;
  if (getPlatformDisplay && hasExtension(clientExtensions, "EGL_EXT_platform_device")) {
    auto queryDevices =
        reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    auto queryDeviceString = reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(
        eglGetProcAddress("eglQueryDeviceStringEXT"));
    EGLint count = 0;
    if (queryDevices && queryDevices(0, nullptr, &count) && count > 0) {
      std::vector<EGLDeviceEXT> devices(count);
      queryDevices(count, devices.data(), &count);
      std::vector<Candidate> software;
      for (EGLint i = 0; i < count; ++i) {
        const char* ext = queryDeviceString ? queryDeviceString(devices[i], EGL_EXTENSIONS) : "";
        const bool isSoftware = hasExtension(ext, "EGL_MESA_device_software");
        Candidate c{
            "EGL device platform, device " + std::to_string(i) +
                (isSoftware ? " (software)" : " (hardware)"),
            [=] { return getPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr); }};
        (isSoftware ? software : candidates).push_back(std::move(c));
      }
      candidates.insert(candidates.end(), software.begin(), software.end());
    }
  }
  if (getPlatformDisplay && hasExtension(clientExtensions, "EGL_MESA_platform_surfaceless")) {
    candidates.push_back({"Mesa surfaceless platform", [=] {
                            return getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA,
                                                      EGL_DEFAULT_DISPLAY, nullptr);
                          }});
  }
  candidates.push_back({"default display", [] { return eglGetDisplay(EGL_DEFAULT_DISPLAY); }});
  return candidates;
}

// Initializes `display` and makes an OpenGL 4.5 core context current on it (surfaceless). On
// failure returns what went wrong, with nothing left open; "" on success.
std::string makeContextCurrent(EGLDisplay display, EGLContext& context) {
  if (!eglInitialize(display, nullptr, nullptr)) {
    return "eglInitialize failed (" + eglErrorName(eglGetError()) + ")";
  }
  // The reason is formed (and the EGL error read) before the display is terminated.
  const auto terminated = [display](std::string why) {
    eglTerminate(display);
    return why;
  };
  if (!hasExtension(eglQueryString(display, EGL_EXTENSIONS), "EGL_KHR_surfaceless_context")) {
    return terminated("no EGL_KHR_surfaceless_context");
  }
  if (!eglBindAPI(EGL_OPENGL_API)) {
    return terminated("no desktop OpenGL (" + eglErrorName(eglGetError()) + ")");
  }
  const EGLint configAttribs[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE,
                                  EGL_OPENGL_BIT, EGL_NONE};
  EGLConfig config = nullptr;
  EGLint numConfigs = 0;
  if (!eglChooseConfig(display, configAttribs, &config, 1, &numConfigs) || numConfigs < 1) {
    return terminated("no OpenGL config");
  }
  const EGLint contextAttribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                                   4,
                                   EGL_CONTEXT_MINOR_VERSION,
                                   5,
                                   EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                   EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                   EGL_NONE};
  context = eglCreateContext(display, config, EGL_NO_CONTEXT, contextAttribs);
  if (context == EGL_NO_CONTEXT) {
    return terminated("no OpenGL 4.5 core context (" + eglErrorName(eglGetError()) + ")");
  }
  if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
    const std::string why = "eglMakeCurrent failed (" + eglErrorName(eglGetError()) + ")";
    eglDestroyContext(display, context);
    return terminated(why);
  }
  GLint major = 0, minor = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &major);
  glGetIntegerv(GL_MINOR_VERSION, &minor);
  if (major * 10 + minor < 45) {
    eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(display, context);
    return terminated("OpenGL " + std::to_string(major) + "." + std::to_string(minor) +
                      " is older than the 4.5 needed");
  }
  return {};
}

std::string glString(GLenum name) {
  const GLubyte* s = glGetString(name);
  return s ? std::string(reinterpret_cast<const char*>(s)) : std::string();
}

}  // namespace

GlContext::GlContext() {
  std::string attempts;
  for (const Candidate& c : displayCandidates()) {
    EGLDisplay display = c.open();
    EGLContext context = EGL_NO_CONTEXT;
    const std::string failure = display == EGL_NO_DISPLAY
                                    ? "no display (" + eglErrorName(eglGetError()) + ")"
                                    : makeContextCurrent(display, context);
    if (!failure.empty()) {
      attempts += (attempts.empty() ? "" : "; ") + c.label + ": " + failure;
      continue;
    }
    display_ = display;
    context_ = context;
    eglPath_ = c.label;
    const char* eglVendor = eglQueryString(display, EGL_VENDOR);
    eglVendor_ = eglVendor ? eglVendor : "";
    glVendor_ = glString(GL_VENDOR);
    glRenderer_ = glString(GL_RENDERER);
    glVersion_ = glString(GL_VERSION);
    glGetIntegerv(GL_MAX_SAMPLES, &maxSamples_);
    maxVertexStorageBytes_ = currentMaxVertexStorageBytes();
    software_ = glRenderer_.find("llvmpipe") != std::string::npos ||
                glRenderer_.find("softpipe") != std::string::npos ||
                c.label.find("(software)") != std::string::npos;
    return;
  }
  throw Error("no EGL display gives an OpenGL 4.5 core context (" +
              (attempts.empty() ? std::string("no EGL display found") : attempts) +
              "); install Mesa (libgl1-mesa-dri, libegl1) or a GPU driver with EGL");
}

GlContext::~GlContext() {
  if (!display_) return;
  eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(display_, context_);
  eglTerminate(display_);
}

std::size_t currentMaxVertexStorageBytes() {
  GLint vertexBlocks = 0;
  GLint64 blockBytes = 0;
  glGetIntegerv(GL_MAX_VERTEX_SHADER_STORAGE_BLOCKS, &vertexBlocks);
  glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &blockBytes);
  return vertexBlocks > 0 && blockBytes > 0 ? std::size_t(blockBytes) : 0;
}

}  // namespace sss
