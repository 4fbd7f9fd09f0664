// The renderer's render targets: the offscreen framebuffer, the colour attachments it shares with
// the background cache, the sun's shadow map; and their deletion.
#include <string>

#include "renderer/gl_state.h"

namespace aar_sim::render {

void CheckGl(const char* what) {
  const GLenum e = glGetError();
  if (e != GL_NO_ERROR)
    throw RenderError(std::string(what) + ": OpenGL error " + std::to_string(e));
}

void AttachColorTargets(int width, int height, GLuint color[3]) {
  glGenRenderbuffers(3, color);
  // Radiance in float: the sensor model (sensor.h) makes the grey levels.
  const GLenum formats[3] = {GL_R32F, GL_R8UI, GL_R32F};
  for (int i = 0; i < 3; ++i) {
    glBindRenderbuffer(GL_RENDERBUFFER, color[i]);
    glRenderbufferStorage(GL_RENDERBUFFER, formats[i], width, height);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + i, GL_RENDERBUFFER, color[i]);
  }
}

void DrawToColorTargets(const char* incomplete) {
  const GLenum buffers[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
  glDrawBuffers(3, buffers);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    throw RenderError(incomplete);
  }
}

void CreateFramebuffer(const CameraIntrinsics& k, Renderer::Gl* gl) {
  glGenFramebuffers(1, &gl->framebuffer);
  glBindFramebuffer(GL_FRAMEBUFFER, gl->framebuffer);
  AttachColorTargets(k.width, k.height, gl->color);
  glGenRenderbuffers(1, &gl->depth_buffer);
  glBindRenderbuffer(GL_RENDERBUFFER, gl->depth_buffer);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, k.width, k.height);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, gl->depth_buffer);
  DrawToColorTargets("offscreen framebuffer is incomplete");
}

// A depth texture compared in the shader (sampler2DShadow); outside it, lit.
void CreateShadowMap(int size, Renderer::Gl* gl) {
  glGenTextures(1, &gl->shadow_map);
  glBindTexture(GL_TEXTURE_2D, gl->shadow_map);
  glTexStorage2D(GL_TEXTURE_2D, 1, GL_DEPTH_COMPONENT32F, size, size);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_BORDER);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_BORDER);
  const float far_border[4] = {1, 1, 1, 1};
  glTexParameterfv(GL_TEXTURE_2D, GL_TEXTURE_BORDER_COLOR, far_border);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
  glGenFramebuffers(1, &gl->shadow_framebuffer);
  glBindFramebuffer(GL_FRAMEBUFFER, gl->shadow_framebuffer);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, gl->shadow_map, 0);
  glDrawBuffer(GL_NONE);
  glReadBuffer(GL_NONE);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw RenderError("the sun's shadow-map framebuffer is incomplete");
}

void DeleteObjects(const Renderer::Gl& gl) {
  for (const Mesh& m : gl.meshes) {
    glDeleteBuffers(1, &m.vbo);
    glDeleteVertexArrays(1, &m.vao);
  }
  glDeleteRenderbuffers(3, gl.color);
  glDeleteRenderbuffers(1, &gl.depth_buffer);
  glDeleteFramebuffers(1, &gl.framebuffer);
  glDeleteProgram(gl.program);
  glDeleteProgram(gl.propeller_program);
  glDeleteVertexArrays(1, &gl.empty_vao);
  if (gl.sun_program) {
    glDeleteProgram(gl.sun_program);
    glDeleteProgram(gl.shadow_program);
    glDeleteFramebuffers(1, &gl.shadow_framebuffer);
    glDeleteTextures(1, &gl.shadow_map);
  }
  if (gl.background_program) glDeleteProgram(gl.background_program);
  for (const CachedBackground& b : gl.backgrounds) {
    glDeleteRenderbuffers(3, b.color);
    glDeleteFramebuffers(1, &b.framebuffer);
  }
  if (gl.background_vao) glDeleteVertexArrays(1, &gl.background_vao);
}

}  // namespace aar_sim::render
