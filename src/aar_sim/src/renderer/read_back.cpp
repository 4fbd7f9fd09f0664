// Read-back: the framebuffer's attachments into images (row 0 at the top), and the 8-bit
// conversion of a radiance image as OpenGL does it (Renderer::ConvertLikeR8Attachment).
#include <algorithm>

#include "renderer/gl_state.h"
#include "renderer/shaders.h"

namespace aar_sim {
namespace render {
namespace {

// One attachment of the bound framebuffer; OpenGL's row 0 is the bottom one, so the rows are
// swapped in place after the read (no second frame-sized buffer to allocate and fill).
template <typename T>
void ReadAttachment(const CameraIntrinsics& k, GLenum attachment, GLenum format, GLenum type,
                    Image<T>* image) {
  image->width = k.width;
  image->height = k.height;
  image->data.resize(static_cast<size_t>(k.width) * k.height);
  glReadBuffer(attachment);
  glReadPixels(0, 0, k.width, k.height, format, type, image->data.data());
  for (int v = 0; v < k.height / 2; ++v) {
    T* top = &image->data[static_cast<size_t>(v) * k.width];
    std::swap_ranges(top, top + k.width,
                     &image->data[static_cast<size_t>(k.height - 1 - v) * k.width]);
  }
}

// The radiance as a float texture in unit 0 (pixel for pixel: no flip, as none on read-back).
GLuint UploadRadiance(const Image<float>& radiance) {
  GLuint texture = 0;
  glGenTextures(1, &texture);
  glBindTexture(GL_TEXTURE_2D, texture);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);  // complete without mipmaps
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_R32F, radiance.width, radiance.height, 0, GL_RED, GL_FLOAT,
               radiance.data.data());
  return texture;
}

struct R8Target {
  GLuint framebuffer = 0, color = 0;
};

// A framebuffer with one 8-bit normalised colour attachment, bound.
R8Target CreateR8Target(int width, int height) {
  R8Target t;
  glGenFramebuffers(1, &t.framebuffer);
  glBindFramebuffer(GL_FRAMEBUFFER, t.framebuffer);
  glGenRenderbuffers(1, &t.color);
  glBindRenderbuffer(GL_RENDERBUFFER, t.color);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_R8, width, height);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, t.color);
  return t;
}

// Copies texture unit 0 into the bound framebuffer through `program` and reads it back.
Image<uint8_t> DrawAndReadR8(GLuint program, int width, int height) {
  GLuint vao = 0;
  glGenVertexArrays(1, &vao);
  glBindVertexArray(vao);
  glViewport(0, 0, width, height);
  glDisable(GL_DEPTH_TEST);
  glUseProgram(program);
  glUniform1i(glGetUniformLocation(program, "u_radiance"), 0);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  Image<uint8_t> out;
  out.width = width;
  out.height = height;
  out.data.resize(static_cast<size_t>(width) * height);
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glReadPixels(0, 0, width, height, GL_RED, GL_UNSIGNED_BYTE, out.data.data());
  glBindVertexArray(0);
  glDeleteVertexArrays(1, &vao);
  return out;
}

}  // namespace

RenderedView ReadView(const CameraIntrinsics& k, bool want_label, bool want_depth) {
  RenderedView view;
  ReadAttachment(k, GL_COLOR_ATTACHMENT0, GL_RED, GL_FLOAT, &view.radiance);
  if (want_label)
    ReadAttachment(k, GL_COLOR_ATTACHMENT1, GL_RED_INTEGER, GL_UNSIGNED_BYTE, &view.label);
  if (want_depth) ReadAttachment(k, GL_COLOR_ATTACHMENT2, GL_RED, GL_FLOAT, &view.depth);
  return view;
}

Image<uint8_t> ReadLabel(const CameraIntrinsics& k) {
  Image<uint8_t> label;
  ReadAttachment(k, GL_COLOR_ATTACHMENT1, GL_RED_INTEGER, GL_UNSIGNED_BYTE, &label);
  return label;
}

}  // namespace render

Image<uint8_t> Renderer::ConvertLikeR8Attachment(const Image<float>& radiance) {
  render::CurrentContext current(gl_->egl);
  const GLuint program =
      render::LinkFiles("r8_conversion_vertex.glsl", "r8_conversion_fragment.glsl");
  const GLuint texture = render::UploadRadiance(radiance);
  const render::R8Target target = render::CreateR8Target(radiance.width, radiance.height);
  Image<uint8_t> out = render::DrawAndReadR8(program, radiance.width, radiance.height);
  // Back to the renderer's state (Render binds its own framebuffer and program).
  glEnable(GL_DEPTH_TEST);
  glViewport(0, 0, options_.intrinsics.width, options_.intrinsics.height);
  glDeleteRenderbuffers(1, &target.color);
  glDeleteFramebuffers(1, &target.framebuffer);
  glDeleteTextures(1, &texture);
  glDeleteProgram(program);
  render::CheckGl("8-bit conversion");
  return out;
}

}  // namespace aar_sim
