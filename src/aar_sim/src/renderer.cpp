// The renderer: construction (its options checked, the EGL context, programs and targets), mesh
// upload, and a frame as a sequence of passes (renderer/: shadow map, background, meshes,
// propellers, read-back). The GLSL is in the package's shaders/ directory.
#include "aar_sim/renderer.h"

#include "renderer/gl_state.h"
#include "renderer/shaders.h"

namespace aar_sim {
namespace {

void CheckOptions(const RendererOptions& options) {
  const CameraIntrinsics& k = options.intrinsics;
  if (k.width <= 0 || k.height <= 0 || !(k.fx > 0.0) || !(k.fy > 0.0)) {
    throw RenderError("camera intrinsics need a positive size and focal length");
  }
  const SceneOptions& sc = options.scene;
  if (sc.background != Background::kNone) {
    if (!(sc.background_altitude_m > 0.0)) throw RenderError("background_altitude must be > 0");
    if (!(sc.visibility_m > 0.0)) throw RenderError("visibility must be > 0");
    if (!(sc.cloud_coverage >= 0.0 && sc.cloud_coverage <= 1.0))
      throw RenderError("cloud_coverage must be in [0, 1]");
    if (!(sc.cloud_altitude_m > 0.0 && sc.cloud_altitude_m < sc.background_altitude_m))
      throw RenderError("cloud_altitude must be > 0 and below background_altitude");
    if (!(sc.cloud_min_range_m >= 0.0)) throw RenderError("cloud_min_range must not be negative");
  }
  if (options.sun.enabled) options.sun.Validate();
}

// The mesh program (and its sun variant), the background's and the propellers' programs and the
// shadow map's, with the vertex arrays of the passes that draw without vertices.
void CreatePrograms(const RendererOptions& options, Renderer::Gl* gl) {
  const std::string mesh_vertex = render::LoadShader("mesh_vertex.glsl");
  const std::string mesh_fragment = render::LoadShader("mesh_fragment.glsl");
  gl->program = render::Link(mesh_vertex, mesh_fragment);
  if (options.scene.background != Background::kNone) {
    gl->background_program =
        render::LinkFiles("background_vertex.glsl", "background_fragment.glsl");
    glGenVertexArrays(1, &gl->background_vao);
  }
  gl->propeller_program = render::LinkFiles("propeller_vertex.glsl", "propeller_fragment.glsl");
  glGenVertexArrays(1, &gl->empty_vao);
  if (options.sun.enabled) {
    // The same source with SUN defined: a program of its own, so that the ideal world's program
    // stays the one whose images the tests compare bit for bit.
    gl->sun_program = render::Link(render::WithSun(mesh_vertex), render::WithSun(mesh_fragment));
    gl->shadow_program = render::LinkFiles("shadow_vertex.glsl", "shadow_fragment.glsl");
  }
}

// Flat shading: every triangle gets its own three vertices with the face normal and part.
std::vector<float> FlatVertices(const aar_geometry::TriangleMesh& mesh) {
  std::vector<float> data;
  data.reserve(mesh.triangles.size() * 3 * 7);
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Eigen::Vector3d n = mesh.TriangleNormal(static_cast<int>(t));
    for (int c = 0; c < 3; ++c) {
      const Eigen::Vector3d& p = mesh.vertices[mesh.triangles[t][c]];
      data.insert(data.end(),
                  {static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()),
                   static_cast<float>(n.x()), static_cast<float>(n.y()), static_cast<float>(n.z()),
                   static_cast<float>(mesh.triangle_parts[t])});
    }
  }
  return data;
}

// A vertex array of FlatVertices: position, normal, part.
void UploadVertices(const std::vector<float>& data, render::Mesh* m) {
  glGenVertexArrays(1, &m->vao);
  glBindVertexArray(m->vao);
  glGenBuffers(1, &m->vbo);
  glBindBuffer(GL_ARRAY_BUFFER, m->vbo);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(data.size() * sizeof(float)), data.data(),
               GL_STATIC_DRAW);
  const GLsizei stride = 7 * sizeof(float);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, nullptr);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride,
                        reinterpret_cast<void*>(3 * sizeof(float)));
  glVertexAttribPointer(2, 1, GL_FLOAT, GL_FALSE, stride,
                        reinterpret_cast<void*>(6 * sizeof(float)));
  for (GLuint i = 0; i < 3; ++i) glEnableVertexAttribArray(i);
  glBindVertexArray(0);
}

}  // namespace

Renderer::Renderer(const RendererOptions& options)
    : options_(options), gl_(std::make_unique<Gl>()) {
  CheckOptions(options_);
  gl_->egl = render::CreateSurfacelessContext();
  render::CurrentContext current(gl_->egl);
  CreatePrograms(options_, gl_.get());
  if (options_.sun.enabled) render::CreateShadowMap(options_.sun.shadow_map_size, gl_.get());
  const CameraIntrinsics& k = options_.intrinsics;
  render::CreateFramebuffer(k, gl_.get());
  glViewport(0, 0, k.width, k.height);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  render::CheckGl("renderer set-up");
}

Renderer::~Renderer() {
  render::DestroyContext(gl_->egl, [this] { render::DeleteObjects(*gl_); });
}

std::string Renderer::gl_renderer() const {
  render::CurrentContext current(gl_->egl);
  return reinterpret_cast<const char*>(glGetString(GL_RENDERER));
}

int Renderer::AddMesh(const aar_geometry::TriangleMesh& mesh, Label label, Surface surface,
                      const Eigen::AlignedBox3d& glass) {
  mesh.Validate();
  render::CurrentContext current(gl_->egl);
  const std::vector<float> data = FlatVertices(mesh);
  render::Mesh m;
  m.label = label;
  m.surface = surface;
  m.glass = glass;
  for (const Eigen::Vector3d& p : mesh.vertices) m.box.extend(p);
  m.vertices = static_cast<GLsizei>(mesh.triangles.size() * 3);
  UploadVertices(data, &m);
  render::CheckGl("mesh upload");
  gl_->meshes.push_back(m);
  return static_cast<int>(gl_->meshes.size()) - 1;
}

RenderedView Renderer::Render(const Eigen::Isometry3d& T_tanker_optical,
                              const std::vector<DrawItem>& items, bool want_label, bool want_depth,
                              const std::vector<PropellerItem>& propellers) {
  render::CurrentContext current(gl_->egl);
  const SunOptions& sun = options_.sun;
  const Eigen::Matrix4d shadow_clip_from_tanker =
      sun.enabled && sun.shadows ? render::UpdateShadowMap(sun, items, gl_.get())
                                 : Eigen::Matrix4d::Identity();
  render::ClearToSky(options_, *gl_);
  if (gl_->background_program) render::CopyBackground(options_, T_tanker_optical, gl_.get());
  render::DrawMeshes(options_, T_tanker_optical, shadow_clip_from_tanker, items, *gl_);
  if (!propellers.empty()) render::DrawPropellers(options_, T_tanker_optical, propellers, *gl_);
  RenderedView view = render::ReadView(options_.intrinsics, want_label, want_depth);
  render::CheckGl("render");
  return view;
}

Image<uint8_t> Renderer::RenderLabel(const Eigen::Isometry3d& T_tanker_optical,
                                     const std::vector<DrawItem>& items) {
  render::CurrentContext current(gl_->egl);
  // The label does not depend on the light: the plain program, no shadow map.
  RendererOptions unlit = options_;
  unlit.sun.enabled = false;
  render::ClearToSky(unlit, *gl_);
  render::DrawMeshes(unlit, T_tanker_optical, Eigen::Matrix4d::Identity(), items, *gl_);
  Image<uint8_t> label = render::ReadLabel(options_.intrinsics);
  render::CheckGl("label render");
  return label;
}

}  // namespace aar_sim
