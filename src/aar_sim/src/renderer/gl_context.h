#pragma once

// The renderer's EGL side: an OpenGL 4.5 core context with no surface and no display server,
// bound for one call at a time. Private to the library.

#include <epoxy/egl.h>

#include <functional>

namespace aar_sim::render {

struct EglContext {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
};

// A GPU's EGL device where there is one, else Mesa's surfaceless platform (llvmpipe), and an
// OpenGL 4.5 core context on it. Throws RenderError saying what was tried.
EglContext CreateSurfacelessContext();

// Binds the context on the calling thread; throws RenderError if EGL refuses.
void MakeCurrent(const EglContext& egl);

// Binds the context, lets `delete_objects` free what lives in it, then releases and destroys the
// context; does nothing if there is no context or it cannot be bound. The display is left open:
// it is shared by every renderer of the process, and terminating it breaks the others (two sim
// nodelets in one manager, say).
void DestroyContext(const EglContext& egl, const std::function<void()>& delete_objects);

// Binds the context for one call and releases it after, so that any thread may make the next
// call (a context can be current on one thread only).
class CurrentContext {
 public:
  explicit CurrentContext(const EglContext& egl) : display_(egl.display) { MakeCurrent(egl); }
  ~CurrentContext() { eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT); }
  CurrentContext(const CurrentContext&) = delete;
  CurrentContext& operator=(const CurrentContext&) = delete;

 private:
  EGLDisplay display_;
};

}  // namespace aar_sim::render
