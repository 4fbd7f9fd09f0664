#include "aar_sim/renderer.h"

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>

namespace aar_sim {
namespace {

const char* kVertexShader = R"(#version 450 core
layout(location = 0) in vec3 in_position;  // object frame [m]
layout(location = 1) in vec3 in_normal;    // object frame
layout(location = 2) in float in_part;
uniform mat4 u_optical_from_object;
uniform mat3 u_tanker_from_object;
uniform vec4 u_projection;  // 2fx/w, 2(cx+0.5)/w - 1, 2fy/h, 1 - 2(cy+0.5)/h
uniform vec2 u_depth;       // z_clip = a z + b
out vec3 v_object;
out vec3 v_normal;
out float v_depth;
flat out int v_part;
void main() {
  vec3 p = (u_optical_from_object * vec4(in_position, 1.0)).xyz;
  v_object = in_position;
  v_normal = u_tanker_from_object * in_normal;
  v_depth = p.z;
  v_part = int(in_part + 0.5);
  gl_Position = vec4(u_projection.x * p.x + u_projection.y * p.z,
                     -u_projection.z * p.y + u_projection.w * p.z,
                     u_depth.x * p.z + u_depth.y, p.z);
}
)";

// Procedural texture from object-space position: no UVs, identical for both cameras, and faded
// octave by octave as the pixel footprint grows so that distant surfaces do not alias.
const char* kFragmentShader = R"(#version 450 core
in vec3 v_object;
in vec3 v_normal;
in float v_depth;
flat in int v_part;
uniform int u_label;
uniform int u_surface;  // 0 aircraft paint, 1 boom stripes
uniform vec3 u_sun;
layout(location = 0) out float out_intensity;
layout(location = 1) out uint out_label;
layout(location = 2) out float out_depth;

uint Hash(uvec3 v) {  // PCG3D
  v = v * 1664525u + 1013904223u;
  v.x += v.y * v.z; v.y += v.z * v.x; v.z += v.x * v.y;
  v ^= v >> 16u;
  v.x += v.y * v.z; v.y += v.z * v.x; v.z += v.x * v.y;
  return v.x ^ v.y ^ v.z;
}
float Lattice(ivec3 i, uint salt) { return float(Hash(uvec3(i) + uvec3(salt, 7u * salt, 13u * salt)) & 0xffffu) / 65535.0; }
float ValueNoise(vec3 p, uint salt) {
  ivec3 i = ivec3(floor(p));
  vec3 f = fract(p);
  vec3 s = f * f * (3.0 - 2.0 * f);
  float x00 = mix(Lattice(i, salt), Lattice(i + ivec3(1, 0, 0), salt), s.x);
  float x10 = mix(Lattice(i + ivec3(0, 1, 0), salt), Lattice(i + ivec3(1, 1, 0), salt), s.x);
  float x01 = mix(Lattice(i + ivec3(0, 0, 1), salt), Lattice(i + ivec3(1, 0, 1), salt), s.x);
  float x11 = mix(Lattice(i + ivec3(0, 1, 1), salt), Lattice(i + ivec3(1, 1, 1), salt), s.x);
  return mix(mix(x00, x10, s.y), mix(x01, x11, s.y), s.z);
}
// Octave weight: 1 while the feature size spans several pixels, 0 once it is below one.
float Visible(float size, float footprint) { return 1.0 - smoothstep(0.5 * size, 1.5 * size, footprint); }
// 1 on a line of width w repeating every `period` along coordinate c, antialiased.
float Line(float c, float period, float w, float footprint) {
  float d = abs(fract(c / period + 0.5) - 0.5) * period;
  return (1.0 - smoothstep(0.5 * w, 0.5 * w + footprint, d)) * Visible(w, footprint);
}

void main() {
  float footprint = max(length(fwidth(v_object)), 1e-5);  // [m] per pixel
  uint salt = uint(v_part) * 97u + 11u;
  float albedo;
  if (u_surface == 1) {
    // Boom: light grey with dark bands every 1.2 m along the boom, then wear.
    float band = Line(v_object.x, 1.2, 0.4, footprint);
    albedo = mix(0.80, 0.22, band);
  } else {
    // Aircraft paint: a grey per part, a darker cheat line along the fuselage, panel lines.
    albedo = 0.70 + 0.06 * (float(Hash(uvec3(salt)) & 255u) / 255.0 - 0.5);
    albedo -= 0.30 * (1.0 - smoothstep(0.08, 0.08 + footprint, abs(v_object.z - 0.15)))
              * float(v_part <= 1);
    float panels = max(Line(v_object.x, 0.55, 0.015, footprint), Line(v_object.y, 0.85, 0.015, footprint));
    panels = max(panels, Line(v_object.z, 0.45, 0.012, footprint));
    albedo -= 0.35 * panels;
  }
  // Paint variation and grime at 1.5 m, 0.4 m, 0.12 m and 0.04 m.
  float n = 0.0;
  n += 0.16 * (ValueNoise(v_object / 1.5, salt) - 0.5);
  n += 0.16 * (ValueNoise(v_object / 0.4, salt + 1u) - 0.5) * Visible(0.4, footprint);
  n += 0.20 * (ValueNoise(v_object / 0.12, salt + 2u) - 0.5) * Visible(0.12, footprint);
  n += 0.20 * (ValueNoise(v_object / 0.04, salt + 3u) - 0.5) * Visible(0.04, footprint);
  albedo = clamp(albedo + n, 0.05, 0.95);

  float shade = 0.45 + 0.55 * abs(dot(normalize(v_normal), u_sun));
  out_intensity = clamp(albedo * shade, 0.0, 1.0);
  out_label = uint(u_label);
  out_depth = v_depth;
}
)";

struct Mesh {
  GLuint vao = 0, vbo = 0;
  GLsizei vertices = 0;
  Label label;
  Surface surface;
};

GLuint Compile(GLenum type, const char* source) {
  const GLuint shader = glCreateShader(type);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[4096];
    glGetShaderInfoLog(shader, sizeof(log), nullptr, log);
    throw RenderError(std::string("shader does not compile: ") + log);
  }
  return shader;
}

// Inverse of the standard normal CDF (Acklam's rational approximation, relative error < 1.2e-9).
double NormalQuantile(double p) {
  static const double a[] = {-3.969683028665376e+01, 2.209460984245205e+02,  -2.759285104469687e+02,
                             1.383577518672690e+02,  -3.066479806614716e+01, 2.506628277459239e+00};
  static const double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                             6.680131188771972e+01, -1.328068155288572e+01};
  static const double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                             -2.549732539343734e+00, 4.374664141464968e+00,  2.938163982698783e+00};
  static const double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                             3.754408661907416e+00};
  if (p < 0.02425) {
    const double q = std::sqrt(-2.0 * std::log(p));
    return (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
           ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
  }
  if (p > 1.0 - 0.02425) return -NormalQuantile(1.0 - p);
  const double q = p - 0.5, r = q * q;
  return (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
         (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1.0);
}

// Standard normal samples indexed by 16 random bits: 65536 equiprobable quantiles (tails cut at
// 4.3 sigma). Four pixels per 64-bit draw; Box-Muller per pixel cost 45 ms a 1280x960 view.
const std::vector<float>& NormalTable() {
  static const std::vector<float> table = [] {
    std::vector<float> t(65536);
    for (size_t i = 0; i < t.size(); ++i)
      t[i] = static_cast<float>(NormalQuantile((i + 0.5) / 65536.0));
    return t;
  }();
  return table;
}

void CheckGl(const char* what) {
  const GLenum e = glGetError();
  if (e != GL_NO_ERROR)
    throw RenderError(std::string(what) + ": OpenGL error " + std::to_string(e));
}

}  // namespace

struct Renderer::Gl {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
  GLuint program = 0, framebuffer = 0;
  GLuint color[3] = {0, 0, 0};  // intensity R8, label R8UI, depth R32F
  GLuint depth_buffer = 0;
  std::vector<Mesh> meshes;

  void MakeCurrent() const {
    if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
      throw RenderError("eglMakeCurrent failed (EGL error " + std::to_string(eglGetError()) + ")");
    }
  }
};

namespace {

// Binds the context for one call and releases it after, so that any thread may make the next
// call (a context can be current on one thread only).
class CurrentContext {
 public:
  explicit CurrentContext(const Renderer::Gl& gl) : display_(gl.display) { gl.MakeCurrent(); }
  ~CurrentContext() { eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT); }
  CurrentContext(const CurrentContext&) = delete;
  CurrentContext& operator=(const CurrentContext&) = delete;

 private:
  EGLDisplay display_;
};

}  // namespace

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

}  // namespace

Renderer::Renderer(const RendererOptions& options)
    : options_(options), gl_(std::make_unique<Gl>()) {
  const CameraIntrinsics& k = options_.intrinsics;
  if (k.width <= 0 || k.height <= 0 || !(k.fx > 0.0) || !(k.fy > 0.0)) {
    throw RenderError("camera intrinsics need a positive size and focal length");
  }
  std::string tried;
  gl_->display = OpenDisplay(&tried);
  if (gl_->display == EGL_NO_DISPLAY) throw RenderError("no EGL display available: " + tried);
  if (!eglBindAPI(EGL_OPENGL_API)) throw RenderError("EGL cannot bind the OpenGL API");
  const EGLint context_attributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                                       4,
                                       EGL_CONTEXT_MINOR_VERSION,
                                       5,
                                       EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                       EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                       EGL_NONE};
  gl_->context =
      eglCreateContext(gl_->display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, context_attributes);
  if (gl_->context == EGL_NO_CONTEXT) {
    throw RenderError("no OpenGL 4.5 core context (EGL error " + std::to_string(eglGetError()) +
                      ")");
  }
  CurrentContext current(*gl_);

  const GLuint vs = Compile(GL_VERTEX_SHADER, kVertexShader);
  const GLuint fs = Compile(GL_FRAGMENT_SHADER, kFragmentShader);
  gl_->program = glCreateProgram();
  glAttachShader(gl_->program, vs);
  glAttachShader(gl_->program, fs);
  glLinkProgram(gl_->program);
  GLint linked = 0;
  glGetProgramiv(gl_->program, GL_LINK_STATUS, &linked);
  glDeleteShader(vs);
  glDeleteShader(fs);
  if (!linked) throw RenderError("shader program does not link");

  glGenFramebuffers(1, &gl_->framebuffer);
  glBindFramebuffer(GL_FRAMEBUFFER, gl_->framebuffer);
  glGenRenderbuffers(3, gl_->color);
  const GLenum formats[3] = {GL_R8, GL_R8UI, GL_R32F};
  for (int i = 0; i < 3; ++i) {
    glBindRenderbuffer(GL_RENDERBUFFER, gl_->color[i]);
    glRenderbufferStorage(GL_RENDERBUFFER, formats[i], k.width, k.height);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + i, GL_RENDERBUFFER,
                              gl_->color[i]);
  }
  glGenRenderbuffers(1, &gl_->depth_buffer);
  glBindRenderbuffer(GL_RENDERBUFFER, gl_->depth_buffer);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, k.width, k.height);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER,
                            gl_->depth_buffer);
  const GLenum buffers[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
  glDrawBuffers(3, buffers);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    throw RenderError("offscreen framebuffer is incomplete");
  }
  glViewport(0, 0, k.width, k.height);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  CheckGl("renderer set-up");
}

Renderer::~Renderer() {
  if (gl_->display == EGL_NO_DISPLAY) return;
  if (gl_->context != EGL_NO_CONTEXT &&
      eglMakeCurrent(gl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, gl_->context)) {
    for (const Mesh& m : gl_->meshes) {
      glDeleteBuffers(1, &m.vbo);
      glDeleteVertexArrays(1, &m.vao);
    }
    glDeleteRenderbuffers(3, gl_->color);
    glDeleteRenderbuffers(1, &gl_->depth_buffer);
    glDeleteFramebuffers(1, &gl_->framebuffer);
    glDeleteProgram(gl_->program);
    eglMakeCurrent(gl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(gl_->display, gl_->context);
  }
  // No eglTerminate: the display is shared by every renderer of the process, and terminating it
  // breaks the others (two sim nodelets in one manager, say).
}

std::string Renderer::gl_renderer() const {
  CurrentContext current(*gl_);
  return reinterpret_cast<const char*>(glGetString(GL_RENDERER));
}

int Renderer::AddMesh(const aar_geometry::TriangleMesh& mesh, Label label, Surface surface) {
  mesh.Validate();
  CurrentContext current(*gl_);
  // Flat shading: every triangle gets its own three vertices with the face normal and part.
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
  Mesh m;
  m.label = label;
  m.surface = surface;
  m.vertices = static_cast<GLsizei>(mesh.triangles.size() * 3);
  glGenVertexArrays(1, &m.vao);
  glBindVertexArray(m.vao);
  glGenBuffers(1, &m.vbo);
  glBindBuffer(GL_ARRAY_BUFFER, m.vbo);
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
  CheckGl("mesh upload");
  gl_->meshes.push_back(m);
  return static_cast<int>(gl_->meshes.size()) - 1;
}

RenderedView Renderer::Render(const Eigen::Isometry3d& T_tanker_optical,
                              const std::vector<DrawItem>& items, uint64_t view_key,
                              bool want_label, bool want_depth) {
  const CameraIntrinsics& k = options_.intrinsics;
  CurrentContext current(*gl_);
  glBindFramebuffer(GL_FRAMEBUFFER, gl_->framebuffer);
  const float sky[4] = {static_cast<float>(options_.sky_level / 255.0), 0, 0, 0};
  const GLuint background[4] = {static_cast<GLuint>(Label::kBackground), 0, 0, 0};
  const float no_depth[4] = {0, 0, 0, 0};
  glClearBufferfv(GL_COLOR, 0, sky);
  glClearBufferuiv(GL_COLOR, 1, background);
  glClearBufferfv(GL_COLOR, 2, no_depth);
  glClear(GL_DEPTH_BUFFER_BIT);

  glUseProgram(gl_->program);
  const GLint u_optical = glGetUniformLocation(gl_->program, "u_optical_from_object");
  const GLint u_tanker = glGetUniformLocation(gl_->program, "u_tanker_from_object");
  const GLint u_label = glGetUniformLocation(gl_->program, "u_label");
  const GLint u_surface = glGetUniformLocation(gl_->program, "u_surface");
  // Pixel centres: image column u maps to window x = u + 0.5; rows are flipped on read-back.
  glUniform4f(glGetUniformLocation(gl_->program, "u_projection"),
              static_cast<float>(2.0 * k.fx / k.width),
              static_cast<float>(2.0 * (k.cx + 0.5) / k.width - 1.0),
              static_cast<float>(2.0 * k.fy / k.height),
              static_cast<float>(1.0 - 2.0 * (k.cy + 0.5) / k.height));
  const double n = options_.near_m, f = options_.far_m;
  glUniform2f(glGetUniformLocation(gl_->program, "u_depth"), static_cast<float>((f + n) / (f - n)),
              static_cast<float>(-2.0 * f * n / (f - n)));
  const Eigen::Vector3f sun = options_.sun_in_tanker.normalized().cast<float>();
  glUniform3f(glGetUniformLocation(gl_->program, "u_sun"), sun.x(), sun.y(), sun.z());

  const Eigen::Isometry3d T_optical_tanker = T_tanker_optical.inverse();
  for (const DrawItem& item : items) {
    if (item.mesh < 0 || item.mesh >= static_cast<int>(gl_->meshes.size())) {
      throw RenderError("draw item refers to mesh " + std::to_string(item.mesh));
    }
    const Mesh& m = gl_->meshes[item.mesh];
    // Composed in double, uploaded in float: object coordinates stay small, so no precision
    // is lost at 175 m.
    const Eigen::Matrix4f optical_from_object =
        (T_optical_tanker * item.T_tanker_object).matrix().cast<float>();
    const Eigen::Matrix3f tanker_from_object = item.T_tanker_object.linear().cast<float>();
    glUniformMatrix4fv(u_optical, 1, GL_FALSE, optical_from_object.data());
    glUniformMatrix3fv(u_tanker, 1, GL_FALSE, tanker_from_object.data());
    glUniform1i(u_label, static_cast<int>(m.label));
    glUniform1i(u_surface, static_cast<int>(m.surface));
    glBindVertexArray(m.vao);
    glDrawArrays(GL_TRIANGLES, 0, m.vertices);
  }
  glBindVertexArray(0);

  RenderedView view;
  auto read = [&](GLenum attachment, GLenum format, GLenum type, auto& image) {
    image.width = k.width;
    image.height = k.height;
    image.data.resize(static_cast<size_t>(k.width) * k.height);
    using T = typename std::decay_t<decltype(image.data)>::value_type;
    std::vector<T> flipped(image.data.size());
    glReadBuffer(attachment);
    glReadPixels(0, 0, k.width, k.height, format, type, flipped.data());
    for (int v = 0; v < k.height; ++v) {
      std::memcpy(&image.data[static_cast<size_t>(v) * k.width],
                  &flipped[static_cast<size_t>(k.height - 1 - v) * k.width], k.width * sizeof(T));
    }
  };
  read(GL_COLOR_ATTACHMENT0, GL_RED, GL_UNSIGNED_BYTE, view.image);
  if (want_label) read(GL_COLOR_ATTACHMENT1, GL_RED_INTEGER, GL_UNSIGNED_BYTE, view.label);
  if (want_depth) read(GL_COLOR_ATTACHMENT2, GL_RED, GL_FLOAT, view.depth);
  CheckGl("render");

  if (options_.noise_stddev > 0.0) {
    // One stream per (seed, view): reproducible whatever order views are rendered in.
    std::mt19937_64 rng(options_.noise_seed * 0x9E3779B97F4A7C15ull ^
                        (view_key + 1) * 0xD1B54A32D192ED03ull);
    const std::vector<float>& normal = NormalTable();
    const float sigma = static_cast<float>(options_.noise_stddev);
    uint64_t bits = 0;
    for (size_t i = 0; i < view.image.data.size(); ++i) {
      if (i % 4 == 0) bits = rng();
      const float v = view.image.data[i] + sigma * normal[(bits >> (16 * (i % 4))) & 0xffffu];
      view.image.data[i] = static_cast<uint8_t>(std::clamp(std::lround(v), 0L, 255L));
    }
  }
  return view;
}

}  // namespace aar_sim
