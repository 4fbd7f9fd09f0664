#pragma once

// The renderer's OpenGL objects (Renderer::Gl), shared by its passes, and the declarations of the
// passes and set-up steps (their files: gl_context, shaders, render_targets, shadow_pass,
// background_pass, mesh_pass, propeller_pass, read_back). Private to the library.

#include <epoxy/gl.h>

#include <vector>

#include "aar_sim/renderer.h"
#include "renderer/gl_context.h"

namespace aar_sim {
namespace render {

struct Mesh {
  GLuint vao = 0, vbo = 0;
  GLsizei vertices = 0;
  Label label;
  Surface surface;
  Eigen::AlignedBox3d box;    // object frame
  Eigen::AlignedBox3d glass;  // object frame: windscreen (empty: none)
};

// The background pass's output for one camera pose (background_pass.cpp).
struct CachedBackground {
  Eigen::Matrix4d T_tanker_optical;
  GLuint framebuffer = 0;
  GLuint color[3] = {0, 0, 0};
};

// Throws RenderError naming `what` if an OpenGL call since the last check failed.
void CheckGl(const char* what);

}  // namespace render

struct Renderer::Gl {
  render::EglContext egl;
  GLuint program = 0, framebuffer = 0;
  GLuint background_program = 0, background_vao = 0;  // 0 without a background
  GLuint sun_program = 0;                             // 0 without the sun
  GLuint shadow_program = 0, shadow_framebuffer = 0, shadow_map = 0;
  std::vector<DrawItem> shadow_items;  // what the shadow map shows (valid while shadow_valid)
  bool shadow_valid = false;
  Eigen::Matrix4d shadow_clip_from_tanker = Eigen::Matrix4d::Identity();
  GLuint propeller_program = 0, empty_vao = 0;
  // The background pass's output per camera pose: it is fixed in the tanker frame, as the
  // cameras are, so each frame copies it instead of drawing it again (a rig's two cameras).
  std::vector<render::CachedBackground> backgrounds;
  GLuint color[3] = {0, 0, 0};  // radiance R32F, label R8UI, depth R32F
  GLuint depth_buffer = 0;
  std::vector<render::Mesh> meshes;
};

namespace render {

// render_targets.cpp: the offscreen framebuffer (radiance, label, depth and a depth buffer) and
// the sun's shadow map; the background cache's framebuffers share AttachColorTargets.
void CreateFramebuffer(const CameraIntrinsics& k, Renderer::Gl* gl);
// Three renderbuffers (radiance R32F, label R8UI, depth R32F) attached to the bound framebuffer.
void AttachColorTargets(int width, int height, GLuint color[3]);
// Draws into the three colour attachments; throws RenderError(`incomplete`) if the bound
// framebuffer is incomplete.
void DrawToColorTargets(const char* incomplete);
void CreateShadowMap(int size, Renderer::Gl* gl);
// Frees every OpenGL object of `gl` (its context current).
void DeleteObjects(const Renderer::Gl& gl);

// shadow_pass.cpp: the sun's shadow map of `items` (reused while they stay where they were);
// returns the transform from the tanker frame to the map's clip space.
Eigen::Matrix4d UpdateShadowMap(const SunOptions& sun, const std::vector<DrawItem>& items,
                                Renderer::Gl* gl);

// background_pass.cpp: the background pass's radiance, label and depth for this camera pose
// into the framebuffer: drawn once per pose, copied after (the background is fixed in the tanker
// frame).
void CopyBackground(const RendererOptions& options, const Eigen::Isometry3d& T_tanker_optical,
                    Renderer::Gl* gl);

// mesh_pass.cpp: clears the framebuffer to the plain sky; draws the meshes over it.
void ClearToSky(const RendererOptions& options, const Renderer::Gl& gl);
void DrawMeshes(const RendererOptions& options, const Eigen::Isometry3d& T_tanker_optical,
                const Eigen::Matrix4d& shadow_clip_from_tanker, const std::vector<DrawItem>& items,
                const Renderer::Gl& gl);
// The camera's projection and clip planes (u_projection, u_depth) of the mesh and propeller
// programs (bound).
void SetProjection(GLuint program, const RendererOptions& options);

// propeller_pass.cpp: the propellers over what is drawn.
void DrawPropellers(const RendererOptions& options, const Eigen::Isometry3d& T_tanker_optical,
                    const std::vector<PropellerItem>& propellers, const Renderer::Gl& gl);

// read_back.cpp: the framebuffer's radiance, and label and depth when asked for, row 0 at the
// top.
RenderedView ReadView(const CameraIntrinsics& k, bool want_label, bool want_depth);
// The label attachment alone.
Image<uint8_t> ReadLabel(const CameraIntrinsics& k);

}  // namespace render
}  // namespace aar_sim
