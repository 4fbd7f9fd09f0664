// The sun's shadow map: depth along the sun's direction, orthographic, fitted to the boxes of
// what is drawn (docs/realism/sun.md).
#include <algorithm>
#include <cmath>
#include <string>

#include "renderer/gl_state.h"

namespace aar_sim::render {
namespace {

bool SameItems(const std::vector<DrawItem>& a, const std::vector<DrawItem>& b) {
  auto same = [](const DrawItem& x, const DrawItem& y) {
    return x.mesh == y.mesh && x.T_tanker_object.matrix() == y.T_tanker_object.matrix();
  };
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), same);
}

// The sun's frame: z towards the sun, x and y across.
Eigen::Matrix3d SunFromTanker(const SunOptions& sun) {
  const Eigen::Vector3d s = sun.DirectionInTanker();
  const Eigen::Vector3d any =
      std::abs(s.z()) < 0.9 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitX();
  const Eigen::Vector3d x = any.cross(s).normalized(), y = s.cross(x);
  Eigen::Matrix3d R_sun_tanker;
  R_sun_tanker << x.transpose(), y.transpose(), s.transpose();
  return R_sun_tanker;
}

// The items' boxes in the sun's frame, with margins.
Eigen::AlignedBox3d BoundsInSunFrame(const Eigen::Matrix3d& R_sun_tanker,
                                     const std::vector<DrawItem>& items,
                                     const std::vector<Mesh>& meshes) {
  Eigen::AlignedBox3d bounds;
  for (const DrawItem& item : items) {
    if (item.mesh < 0 || item.mesh >= static_cast<int>(meshes.size())) {
      throw RenderError("draw item refers to mesh " + std::to_string(item.mesh));
    }
    const Eigen::AlignedBox3d& box = meshes[item.mesh].box;
    for (int c = 0; c < 8; ++c) {
      bounds.extend(R_sun_tanker * (item.T_tanker_object *
                                    box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c))));
    }
  }
  if (bounds.isEmpty()) bounds.extend(Eigen::Vector3d::Zero());
  bounds.min() -= Eigen::Vector3d(0.5, 0.5, 1.0);  // [m] margins
  bounds.max() += Eigen::Vector3d(0.5, 0.5, 1.0);
  return bounds;
}

// x, y -> [-1, 1] over the bounds (square texels); the sun's z (larger: nearer the sun) -> depth
// -1 (near) .. 1 (far).
Eigen::Matrix4d ClipFromSun(const Eigen::AlignedBox3d& bounds) {
  const Eigen::Vector3d lo = bounds.min(), size = bounds.sizes();
  const double extent = std::max(size.x(), size.y());
  Eigen::Matrix4d clip_from_sun = Eigen::Matrix4d::Identity();
  clip_from_sun(0, 0) = 2.0 / extent;
  clip_from_sun(0, 3) = -1.0 - 2.0 * lo.x() / extent;
  clip_from_sun(1, 1) = 2.0 / extent;
  clip_from_sun(1, 3) = -1.0 - 2.0 * lo.y() / extent;
  clip_from_sun(2, 2) = -2.0 / size.z();
  clip_from_sun(2, 3) = 1.0 + 2.0 * lo.z() / size.z();
  return clip_from_sun;
}

Eigen::Matrix4d FitShadowMap(const SunOptions& sun, const std::vector<DrawItem>& items,
                             const std::vector<Mesh>& meshes) {
  const Eigen::Matrix3d R_sun_tanker = SunFromTanker(sun);
  Eigen::Matrix4d sun_from_tanker = Eigen::Matrix4d::Identity();
  sun_from_tanker.topLeftCorner<3, 3>() = R_sun_tanker;
  return ClipFromSun(BoundsInSunFrame(R_sun_tanker, items, meshes)) * sun_from_tanker;
}

void DrawShadowMap(int size, const Eigen::Matrix4d& clip_from_tanker,
                   const std::vector<DrawItem>& items, const Renderer::Gl& gl) {
  glBindFramebuffer(GL_FRAMEBUFFER, gl.shadow_framebuffer);
  glViewport(0, 0, size, size);
  glClear(GL_DEPTH_BUFFER_BIT);
  glUseProgram(gl.shadow_program);
  const GLint u_clip = glGetUniformLocation(gl.shadow_program, "u_clip_from_object");
  glEnable(GL_POLYGON_OFFSET_FILL);
  glPolygonOffset(1.0f, 2.0f);
  for (const DrawItem& item : items) {
    const Eigen::Matrix4f clip_from_object =
        (clip_from_tanker * item.T_tanker_object.matrix()).cast<float>();
    glUniformMatrix4fv(u_clip, 1, GL_FALSE, clip_from_object.data());
    const Mesh& m = gl.meshes[item.mesh];
    glBindVertexArray(m.vao);
    glDrawArrays(GL_TRIANGLES, 0, m.vertices);
  }
  glBindVertexArray(0);
  glDisable(GL_POLYGON_OFFSET_FILL);
  CheckGl("shadow map");
}

}  // namespace

Eigen::Matrix4d UpdateShadowMap(const SunOptions& sun, const std::vector<DrawItem>& items,
                                Renderer::Gl* gl) {
  if (gl->shadow_valid && SameItems(items, gl->shadow_items)) {
    return gl->shadow_clip_from_tanker;  // the other camera of the pair
  }
  const Eigen::Matrix4d clip_from_tanker = FitShadowMap(sun, items, gl->meshes);
  DrawShadowMap(sun.shadow_map_size, clip_from_tanker, items, *gl);
  gl->shadow_items = items;
  gl->shadow_clip_from_tanker = clip_from_tanker;
  gl->shadow_valid = true;
  return clip_from_tanker;
}

}  // namespace aar_sim::render
