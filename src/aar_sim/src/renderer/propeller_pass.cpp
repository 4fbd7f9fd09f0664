// The propellers (issue 16): a disc per propeller over what is drawn, blended by the fraction of
// the exposure its blades cover each pixel (propeller_fragment.glsl).
#include <cmath>

#include "renderer/gl_state.h"

namespace aar_sim::render {
namespace {

void CheckPropeller(const PropellerItem& prop) {
  if (!(prop.radius_m > prop.hub_radius_m && prop.hub_radius_m >= 0.0 && prop.chord_m > 0.0 &&
        prop.blades > 0 && prop.swept_rad >= 0.0)) {
    throw RenderError(
        "a propeller needs radius > hub radius >= 0, chord > 0, blades > 0 and a "
        "non-negative sweep");
  }
}

void SetPropellerUniforms(GLuint p, const RendererOptions& options, const PropellerItem& prop,
                          const Eigen::Isometry3d& T_optical_tanker) {
  const Eigen::Matrix4f optical_from_disc =
      (T_optical_tanker * prop.T_tanker_disc).matrix().cast<float>();
  glUniformMatrix4fv(glGetUniformLocation(p, "u_optical_from_disc"), 1, GL_FALSE,
                     optical_from_disc.data());
  glUniform1f(glGetUniformLocation(p, "u_radius"), static_cast<float>(prop.radius_m));
  glUniform1f(glGetUniformLocation(p, "u_hub"), static_cast<float>(prop.hub_radius_m));
  glUniform1f(glGetUniformLocation(p, "u_half_chord"), static_cast<float>(0.5 * prop.chord_m));
  glUniform1f(glGetUniformLocation(p, "u_angle"),
              static_cast<float>(std::remainder(prop.angle_rad, 2.0 * M_PI)));
  glUniform1f(glGetUniformLocation(p, "u_swept"), static_cast<float>(prop.swept_rad));
  glUniform1i(glGetUniformLocation(p, "u_blades"), prop.blades);
  // Black blades with white tips, lit as a surface square to the axis.
  const Eigen::Vector3d axis = prop.T_tanker_disc.linear().col(0);
  const SunOptions& sun = options.sun;
  const double facing = std::abs(
      axis.dot(sun.enabled ? sun.DirectionInTanker() : options.sun_in_tanker.normalized()));
  const double shade = sun.enabled ? sun.ambient + sun.direct * facing : 0.45 + 0.55 * facing;
  glUniform2f(glGetUniformLocation(p, "u_blade"), static_cast<float>(0.08 * shade),
              static_cast<float>(0.85 * shade));
}

// Pass 0: the radiance, blended by coverage; pass 1: label and depth where covered most.
void DrawCoverageAndLabel(GLuint p) {
  glUniform1i(glGetUniformLocation(p, "u_pass"), 0);
  glEnablei(GL_BLEND, 0);
  glBlendFunci(0, GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  glColorMaski(1, GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  glColorMaski(2, GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  glDrawArrays(GL_TRIANGLES, 0, 6);
  glDisablei(GL_BLEND, 0);
  glColorMaski(0, GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  glColorMaski(1, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glColorMaski(2, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glUniform1i(glGetUniformLocation(p, "u_pass"), 1);
  glDrawArrays(GL_TRIANGLES, 0, 6);
  glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
}

}  // namespace

void DrawPropellers(const RendererOptions& options, const Eigen::Isometry3d& T_tanker_optical,
                    const std::vector<PropellerItem>& propellers, const Renderer::Gl& gl) {
  const GLuint p = gl.propeller_program;
  glUseProgram(p);
  SetProjection(p, options);
  const Eigen::Isometry3d T_optical_tanker = T_tanker_optical.inverse();
  glBindVertexArray(gl.empty_vao);
  glDepthMask(GL_FALSE);  // translucent: what lies behind stays in the depth buffer
  for (const PropellerItem& prop : propellers) {
    CheckPropeller(prop);
    SetPropellerUniforms(p, options, prop, T_optical_tanker);
    DrawCoverageAndLabel(p);
  }
  glDepthMask(GL_TRUE);
  glBindVertexArray(0);
}

}  // namespace aar_sim::render
