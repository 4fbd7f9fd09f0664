#include "renderer/gl_context.h"

#include <cstring>
#include <string>

#include "aar_sim/renderer.h"

namespace aar_sim::render {
namespace {

// A GPU's EGL device if the driver offers devices, else Mesa's surfaceless platform.
EGLDisplay OpenDisplay(std::string* tried) {
  if (epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_platform_device") &&
      epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_device_enumeration")) {
    EGLDeviceEXT devices[8];
    EGLint count = 0;
    if (eglQueryDevicesEXT(8, devices, &count)) {
      for (EGLint i = 0; i < count; ++i) {
        const char* ext = eglQueryDeviceStringEXT(devices[i], EGL_EXTENSIONS);
        if (ext && std::strstr(ext, "EGL_MESA_device_software")) continue;  // prefer hardware
        EGLDisplay d = eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
        if (d != EGL_NO_DISPLAY && eglInitialize(d, nullptr, nullptr)) return d;
      }
    }
    *tried += "no hardware EGL device; ";
  }
  if (epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_MESA_platform_surfaceless")) {
    EGLDisplay d =
        eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (d != EGL_NO_DISPLAY && eglInitialize(d, nullptr, nullptr)) return d;
    *tried += "Mesa surfaceless platform did not initialise; ";
  } else {
    *tried += "no EGL_MESA_platform_surfaceless (install libegl-mesa0, libgl1-mesa-dri); ";
  }
  return EGL_NO_DISPLAY;
}

EGLContext CreateCoreContext(EGLDisplay display) {
  if (!eglBindAPI(EGL_OPENGL_API)) throw RenderError("EGL cannot bind the OpenGL API");
  const EGLint context_attributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                                       4,
                                       EGL_CONTEXT_MINOR_VERSION,
                                       5,
                                       EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                       EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                       EGL_NONE};
  const EGLContext context =
      eglCreateContext(display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, context_attributes);
  if (context == EGL_NO_CONTEXT) {
    throw RenderError("no OpenGL 4.5 core context (EGL error " + std::to_string(eglGetError()) +
                      ")");
  }
  return context;
}

}  // namespace

EglContext CreateSurfacelessContext() {
  EglContext egl;
  std::string tried;
  egl.display = OpenDisplay(&tried);
  if (egl.display == EGL_NO_DISPLAY) throw RenderError("no EGL display available: " + tried);
  egl.context = CreateCoreContext(egl.display);
  return egl;
}

void MakeCurrent(const EglContext& egl) {
  if (!eglMakeCurrent(egl.display, EGL_NO_SURFACE, EGL_NO_SURFACE, egl.context)) {
    throw RenderError("eglMakeCurrent failed (EGL error " + std::to_string(eglGetError()) + ")");
  }
}

void DestroyContext(const EglContext& egl, const std::function<void()>& delete_objects) {
  if (egl.display == EGL_NO_DISPLAY || egl.context == EGL_NO_CONTEXT) return;
  if (!eglMakeCurrent(egl.display, EGL_NO_SURFACE, EGL_NO_SURFACE, egl.context)) return;
  delete_objects();
  eglMakeCurrent(egl.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(egl.display, egl.context);
}

}  // namespace aar_sim::render
