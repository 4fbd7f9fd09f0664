// The scene pass: the framebuffer cleared to the plain sky, then the meshes (receiver, boom) with
// their procedural surfaces, lit by the ideal world's fixed light or by the sun.
#include <string>

#include "renderer/gl_state.h"

namespace aar_sim::render {
namespace {

// The mesh program's per-item uniforms.
struct ItemUniforms {
  GLint optical_from_object, tanker_from_object, label, surface;
  GLint tanker_offset, sun_from_object, glass_min, glass_max;  // with the sun
};

ItemUniforms FindItemUniforms(GLuint program) {
  ItemUniforms u;
  u.optical_from_object = glGetUniformLocation(program, "u_optical_from_object");
  u.tanker_from_object = glGetUniformLocation(program, "u_tanker_from_object");
  u.label = glGetUniformLocation(program, "u_label");
  u.surface = glGetUniformLocation(program, "u_surface");
  u.tanker_offset = glGetUniformLocation(program, "u_tanker_offset");
  u.sun_from_object = glGetUniformLocation(program, "u_sun_from_object");
  u.glass_min = glGetUniformLocation(program, "u_glass_min");
  u.glass_max = glGetUniformLocation(program, "u_glass_max");
  return u;
}

// The sun's light, skylight, glare and shadow map (the sun program).
void SetSunUniforms(GLuint program, const SunOptions& sun_options,
                    const Eigen::Isometry3d& T_tanker_optical,
                    const Eigen::Matrix4d& shadow_clip_from_tanker, GLuint shadow_map) {
  const Eigen::Vector3f c = T_tanker_optical.translation().cast<float>();
  glUniform3f(glGetUniformLocation(program, "u_camera"), c.x(), c.y(), c.z());
  glUniform1f(glGetUniformLocation(program, "u_direct"), static_cast<float>(sun_options.direct));
  glUniform1f(glGetUniformLocation(program, "u_ambient"), static_cast<float>(sun_options.ambient));
  glUniform3f(glGetUniformLocation(program, "u_specular"),
              static_cast<float>(sun_options.paint_specular),
              static_cast<float>(sun_options.metal_specular),
              static_cast<float>(sun_options.glass_specular));
  glUniform1i(glGetUniformLocation(program, "u_shadows"), sun_options.shadows ? 1 : 0);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, shadow_map);
  glUniform1i(glGetUniformLocation(program, "u_shadow_map"), 0);
  glUniform1f(glGetUniformLocation(program, "u_shadow_texel"),
              static_cast<float>(1.0 / sun_options.shadow_map_size));
  // One texel's size [m] and window depth per metre along the sun (from the fitted map).
  const double texel_m =
      2.0 / shadow_clip_from_tanker.row(0).head<3>().norm() / sun_options.shadow_map_size;
  const double depth_per_m = 0.5 * shadow_clip_from_tanker.row(2).head<3>().norm();
  glUniform2f(glGetUniformLocation(program, "u_shadow_bias"), static_cast<float>(texel_m),
              static_cast<float>(depth_per_m));
}

// The item's glass box, its origin and its transform into the shadow map (the sun program).
void SetItemSunUniforms(const ItemUniforms& u, const Mesh& m, const DrawItem& item,
                        const Eigen::Matrix4d& shadow_clip_from_tanker) {
  // An empty box (min above max) makes no glass.
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(1e9f), hi = Eigen::Vector3f::Constant(-1e9f);
  if (!m.glass.isEmpty()) lo = m.glass.min().cast<float>(), hi = m.glass.max().cast<float>();
  glUniform3f(u.glass_min, lo.x(), lo.y(), lo.z());
  glUniform3f(u.glass_max, hi.x(), hi.y(), hi.z());
  const Eigen::Vector3f offset = item.T_tanker_object.translation().cast<float>();
  glUniform3f(u.tanker_offset, offset.x(), offset.y(), offset.z());
  const Eigen::Matrix4f sun_from_object =
      (shadow_clip_from_tanker * item.T_tanker_object.matrix()).cast<float>();
  glUniformMatrix4fv(u.sun_from_object, 1, GL_FALSE, sun_from_object.data());
}

void DrawMesh(const ItemUniforms& u, const Mesh& m, const DrawItem& item,
              const Eigen::Isometry3d& T_optical_tanker, bool sun,
              const Eigen::Matrix4d& shadow_clip_from_tanker) {
  // Composed in double, uploaded in float: object coordinates stay small, so no precision is lost
  // at 175 m.
  const Eigen::Matrix4f optical_from_object =
      (T_optical_tanker * item.T_tanker_object).matrix().cast<float>();
  const Eigen::Matrix3f tanker_from_object = item.T_tanker_object.linear().cast<float>();
  glUniformMatrix4fv(u.optical_from_object, 1, GL_FALSE, optical_from_object.data());
  glUniformMatrix3fv(u.tanker_from_object, 1, GL_FALSE, tanker_from_object.data());
  if (sun) SetItemSunUniforms(u, m, item, shadow_clip_from_tanker);
  glUniform1i(u.label, static_cast<int>(m.label));
  glUniform1i(u.surface, static_cast<int>(m.surface));
  glBindVertexArray(m.vao);
  glDrawArrays(GL_TRIANGLES, 0, m.vertices);
}

}  // namespace

void SetProjection(GLuint program, const RendererOptions& options) {
  const CameraIntrinsics& k = options.intrinsics;
  // Pixel centres: image column u maps to window x = u + 0.5; rows are flipped on read-back.
  glUniform4f(glGetUniformLocation(program, "u_projection"),
              static_cast<float>(2.0 * k.fx / k.width),
              static_cast<float>(2.0 * (k.cx + 0.5) / k.width - 1.0),
              static_cast<float>(2.0 * k.fy / k.height),
              static_cast<float>(1.0 - 2.0 * (k.cy + 0.5) / k.height));
  const double n = options.near_m, f = options.far_m;
  glUniform2f(glGetUniformLocation(program, "u_depth"), static_cast<float>((f + n) / (f - n)),
              static_cast<float>(-2.0 * f * n / (f - n)));
}

void ClearToSky(const RendererOptions& options, const Renderer::Gl& gl) {
  const CameraIntrinsics& k = options.intrinsics;
  glBindFramebuffer(GL_FRAMEBUFFER, gl.framebuffer);
  glViewport(0, 0, k.width, k.height);
  const float sky[4] = {static_cast<float>(options.sky_level / 255.0), 0, 0, 0};
  const GLuint background[4] = {static_cast<GLuint>(Label::kBackground), 0, 0, 0};
  const float no_depth[4] = {0, 0, 0, 0};
  glClearBufferfv(GL_COLOR, 0, sky);
  glClearBufferuiv(GL_COLOR, 1, background);
  glClearBufferfv(GL_COLOR, 2, no_depth);
  glClear(GL_DEPTH_BUFFER_BIT);
}

void DrawMeshes(const RendererOptions& options, const Eigen::Isometry3d& T_tanker_optical,
                const Eigen::Matrix4d& shadow_clip_from_tanker, const std::vector<DrawItem>& items,
                const Renderer::Gl& gl) {
  const SunOptions& sun_options = options.sun;
  const bool sun = sun_options.enabled;
  const GLuint program = sun ? gl.sun_program : gl.program;
  glUseProgram(program);
  const ItemUniforms u = FindItemUniforms(program);
  SetProjection(program, options);
  const Eigen::Vector3f light =
      (sun ? sun_options.DirectionInTanker() : options.sun_in_tanker.normalized()).cast<float>();
  glUniform3f(glGetUniformLocation(program, "u_sun"), light.x(), light.y(), light.z());
  if (sun) {
    SetSunUniforms(program, sun_options, T_tanker_optical, shadow_clip_from_tanker, gl.shadow_map);
  }
  const Eigen::Isometry3d T_optical_tanker = T_tanker_optical.inverse();
  for (const DrawItem& item : items) {
    if (item.mesh < 0 || item.mesh >= static_cast<int>(gl.meshes.size())) {
      throw RenderError("draw item refers to mesh " + std::to_string(item.mesh));
    }
    DrawMesh(u, gl.meshes[item.mesh], item, T_optical_tanker, sun, shadow_clip_from_tanker);
  }
  glBindVertexArray(0);
}

}  // namespace aar_sim::render
