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

}  // namespace

GlContext::GlContext() {
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

  std::string attempts;
  auto note = [&](const std::string& label, const std::string& what) {
    attempts += (attempts.empty() ? "" : "; ") + label + ": " + what;
  };
  for (const Candidate& c : candidates) {
    EGLDisplay display = c.open();
    if (display == EGL_NO_DISPLAY) {
      note(c.label, "no display (" + eglErrorName(eglGetError()) + ")");
      continue;
    }
    if (!eglInitialize(display, nullptr, nullptr)) {
      note(c.label, "eglInitialize failed (" + eglErrorName(eglGetError()) + ")");
      continue;
    }
    const char* displayExtensions = eglQueryString(display, EGL_EXTENSIONS);
    if (!hasExtension(displayExtensions, "EGL_KHR_surfaceless_context")) {
      note(c.label, "no EGL_KHR_surfaceless_context");
      eglTerminate(display);
      continue;
    }
    if (!eglBindAPI(EGL_OPENGL_API)) {
      note(c.label, "no desktop OpenGL (" + eglErrorName(eglGetError()) + ")");
      eglTerminate(display);
      continue;
    }
    const EGLint configAttribs[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE,
                                    EGL_OPENGL_BIT, EGL_NONE};
    EGLConfig config = nullptr;
    EGLint numConfigs = 0;
    if (!eglChooseConfig(display, configAttribs, &config, 1, &numConfigs) || numConfigs < 1) {
      note(c.label, "no OpenGL config");
      eglTerminate(display);
      continue;
    }
    const EGLint contextAttribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                                     4,
                                     EGL_CONTEXT_MINOR_VERSION,
                                     5,
                                     EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                     EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                     EGL_NONE};
    EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, contextAttribs);
    if (context == EGL_NO_CONTEXT) {
      note(c.label, "no OpenGL 4.5 core context (" + eglErrorName(eglGetError()) + ")");
      eglTerminate(display);
      continue;
    }
    if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
      note(c.label, "eglMakeCurrent failed (" + eglErrorName(eglGetError()) + ")");
      eglDestroyContext(display, context);
      eglTerminate(display);
      continue;
    }
    GLint major = 0, minor = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &major);
    glGetIntegerv(GL_MINOR_VERSION, &minor);
    if (major * 10 + minor < 45) {
      note(c.label, "OpenGL " + std::to_string(major) + "." + std::to_string(minor) +
                        " is older than the 4.5 needed");
      eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
      eglDestroyContext(display, context);
      eglTerminate(display);
      continue;
    }
    display_ = display;
    context_ = context;
    eglPath_ = c.label;
    const char* eglVendor = eglQueryString(display, EGL_VENDOR);
    eglVendor_ = eglVendor ? eglVendor : "";
    auto str = [](GLenum name) {
      const GLubyte* s = glGetString(name);
      return s ? std::string(reinterpret_cast<const char*>(s)) : std::string();
    };
    glVendor_ = str(GL_VENDOR);
    glRenderer_ = str(GL_RENDERER);
    glVersion_ = str(GL_VERSION);
    glGetIntegerv(GL_MAX_SAMPLES, &maxSamples_);
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

}  // namespace sss
