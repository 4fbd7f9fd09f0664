// The background pass (issue 16, docs/realism/scene.md): ground or sea, clouds and haze below the
// tanker, drawn once per camera pose into a cache and copied into the framebuffer after.
#include <algorithm>
#include <cmath>

#include "renderer/gl_state.h"

namespace aar_sim::render {
namespace {

void SetBackgroundUniforms(GLuint p, const RendererOptions& options,
                           const Eigen::Isometry3d& T_tanker_optical) {
  const CameraIntrinsics& k = options.intrinsics;
  const SceneOptions& sc = options.scene;
  glUniform4f(glGetUniformLocation(p, "u_intrinsics"), static_cast<float>(k.fx),
              static_cast<float>(k.fy), static_cast<float>(k.cx), static_cast<float>(k.cy));
  glUniform1f(glGetUniformLocation(p, "u_height"), static_cast<float>(k.height));
  const Eigen::Matrix3f R = T_tanker_optical.linear().cast<float>();
  glUniformMatrix3fv(glGetUniformLocation(p, "u_tanker_from_optical"), 1, GL_FALSE, R.data());
  const Eigen::Vector3f o = T_tanker_optical.translation().cast<float>();
  glUniform3f(glGetUniformLocation(p, "u_camera"), o.x(), o.y(), o.z());
  glUniform1f(glGetUniformLocation(p, "u_sky"), static_cast<float>(options.sky_level / 255.0));
  // The mesh shader's shade of a level surface facing up, so ground and aircraft match.
  const SunOptions& sun = options.sun;
  const double up =
      sun.enabled ? sun.DirectionInTanker().z() : std::abs(options.sun_in_tanker.normalized().z());
  const double shade = sun.enabled ? sun.ambient + sun.direct * up : 0.45 + 0.55 * up;
  glUniform1f(glGetUniformLocation(p, "u_shade"), static_cast<float>(shade));
  glUniform1i(glGetUniformLocation(p, "u_kind"), static_cast<int>(sc.background));
  glUniform1f(glGetUniformLocation(p, "u_ground_z"), static_cast<float>(-sc.background_altitude_m));
  glUniform1f(glGetUniformLocation(p, "u_cloud_z"), static_cast<float>(-sc.cloud_altitude_m));
  glUniform1f(glGetUniformLocation(p, "u_coverage"), static_cast<float>(sc.cloud_coverage));
  glUniform1f(glGetUniformLocation(p, "u_cloud_min_range"),
              static_cast<float>(sc.cloud_min_range_m));
  glUniform1f(glGetUniformLocation(p, "u_visibility"), static_cast<float>(sc.visibility_m));
}

void DrawBackground(const RendererOptions& options, const Eigen::Isometry3d& T_tanker_optical,
                    const Renderer::Gl& gl) {
  glUseProgram(gl.background_program);
  SetBackgroundUniforms(gl.background_program, options, T_tanker_optical);
  glDepthMask(GL_FALSE);
  glBindVertexArray(gl.background_vao);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glDepthMask(GL_TRUE);
}

// A framebuffer of its own with the background drawn for this pose; the renderer's framebuffer
// bound again after.
CachedBackground DrawIntoCache(const RendererOptions& options,
                               const Eigen::Isometry3d& T_tanker_optical, const Renderer::Gl& gl) {
  const CameraIntrinsics& k = options.intrinsics;
  CachedBackground b;
  b.T_tanker_optical = T_tanker_optical.matrix();
  glGenFramebuffers(1, &b.framebuffer);
  glBindFramebuffer(GL_FRAMEBUFFER, b.framebuffer);
  AttachColorTargets(k.width, k.height, b.color);
  DrawToColorTargets("the background cache's framebuffer is incomplete");
  DrawBackground(options, T_tanker_optical, gl);  // covers every pixel (the sky above too)
  glBindFramebuffer(GL_FRAMEBUFFER, gl.framebuffer);
  return b;
}

}  // namespace

void CopyBackground(const RendererOptions& options, const Eigen::Isometry3d& T_tanker_optical,
                    Renderer::Gl* gl) {
  const CameraIntrinsics& k = options.intrinsics;
  auto& cache = gl->backgrounds;
  auto it = std::find_if(cache.begin(), cache.end(), [&](const CachedBackground& b) {
    return b.T_tanker_optical == T_tanker_optical.matrix();
  });
  if (it == cache.end()) {
    if (cache.size() >= 4) {  // a camera that moves: keep the newest few
      glDeleteRenderbuffers(3, cache.front().color);
      glDeleteFramebuffers(1, &cache.front().framebuffer);
      cache.erase(cache.begin());
    }
    cache.push_back(DrawIntoCache(options, T_tanker_optical, *gl));
    it = cache.end() - 1;
  }
  for (int i = 0; i < 3; ++i) {
    glCopyImageSubData(it->color[i], GL_RENDERBUFFER, 0, 0, 0, 0, gl->color[i], GL_RENDERBUFFER, 0,
                       0, 0, 0, k.width, k.height, 1);
  }
  CheckGl("background copy");
}

}  // namespace aar_sim::render
