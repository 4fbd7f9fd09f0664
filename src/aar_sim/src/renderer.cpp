#include "aar_sim/renderer.h"

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace aar_sim {
namespace {

const char* kVertexShader = R"(#version 450 core
layout(location = 0) in vec3 in_position;  // object frame [m]
layout(location = 1) in vec3 in_normal;    // object frame
layout(location = 2) in float in_part;
uniform mat4 u_optical_from_object;
#ifdef SUN
uniform vec3 u_tanker_offset;    // [m] the object's origin in the tanker frame
uniform mat4 u_sun_from_object;  // into the shadow map's clip space
out vec3 v_tanker;
out vec4 v_sun;
flat out float v_up;  // the face normal's object z
#endif
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
#ifdef SUN
  v_tanker = u_tanker_from_object * in_position + u_tanker_offset;
  v_sun = u_sun_from_object * vec4(in_position, 1.0);
  v_up = in_normal.z;
#endif
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
#ifdef SUN
in vec3 v_tanker;
in vec4 v_sun;
flat in float v_up;
uniform vec3 u_glass_min, u_glass_max;  // [m] object frame: the windscreen (empty: none)
uniform vec3 u_camera;  // [m] camera centre, tanker frame
uniform float u_direct, u_ambient;
uniform vec3 u_specular;  // paint, metal, glass
uniform int u_shadows;
uniform sampler2DShadow u_shadow_map;
uniform float u_shadow_texel;  // 1 / map size
uniform vec2 u_shadow_bias;    // [m] one texel's size; depth per metre
#endif
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

#ifdef SUN
  // Skylight, the sun where the shadow map sees this point, and Blinn-Phong glare; the radiance is
  // not clipped here (glare above 1 saturates in the sensor).
  vec3 nrm = normalize(v_normal);
  vec3 to_camera = normalize(u_camera - v_tanker);
  if (dot(nrm, to_camera) < 0.0) nrm = -nrm;  // the side the camera sees
  float specular = u_surface == 1 ? u_specular.y : u_specular.x;
  float shininess = u_surface == 1 ? 60.0 : 25.0;
  bool glass = all(greaterThanEqual(v_object, u_glass_min)) &&
               all(lessThanEqual(v_object, u_glass_max)) && v_up > 0.2;
  if (glass) {  // windscreen: dark tinted glass, a sharp reflection of the sun
    albedo = 0.10 + 0.2 * (albedo - 0.5);
    specular = u_specular.z;
    shininess = 500.0;
  }
  float ns = dot(nrm, u_sun);
  float lit = ns > 0.0 ? 1.0 : 0.0;
  if (u_shadows != 0 && ns > 0.0) {
    vec3 m = v_sun.xyz * 0.5 + 0.5;
    // A grazing sun needs more bias: the surface spans more depth across one texel.
    float slope = sqrt(max(1.0 - ns * ns, 0.0)) / max(ns, 0.2);
    float ref = m.z - u_shadow_bias.y * u_shadow_bias.x * (1.5 + 2.0 * slope);
    float sum = 0.0;  // 3x3 percentage-closer filter of 2x2 hardware comparisons
    for (int i = -1; i <= 1; ++i)
      for (int j = -1; j <= 1; ++j)
        sum += texture(u_shadow_map, vec3(m.xy + vec2(i, j) * u_shadow_texel, ref));
    lit = sum / 9.0;
  }
  vec3 h = normalize(u_sun + to_camera);
  float glare = specular * pow(max(dot(nrm, h), 0.0), shininess) * lit;
  out_intensity = albedo * (u_ambient + u_direct * max(ns, 0.0) * lit) + u_direct * glare;
#else
  float shade = 0.45 + 0.55 * abs(dot(normalize(v_normal), u_sun));
  out_intensity = clamp(albedo * shade, 0.0, 1.0);
#endif
  out_label = uint(u_label);
  out_depth = v_depth;
}
)";

// Background pass (issue 16, docs/realism/scene.md): each pixel's ray meets the ground plane and
// the cloud layer in the tanker frame; texture in tanker x/y [m] (the same for both cameras),
// octaves faded by the pixel footprint, haze towards the sky with distance. Writes its own label
// and optical-z depth; drawn before the meshes with depth writes off, so meshes cover it.
const char* kBackgroundVertexShader = R"(#version 450 core
void main() {  // one triangle over the whole viewport
  vec2 p = vec2(float((gl_VertexID & 1) << 2) - 1.0, float((gl_VertexID & 2) << 1) - 1.0);
  gl_Position = vec4(p, 0.999, 1.0);
}
)";

const char* kBackgroundFragmentShader = R"(#version 450 core
uniform vec4 u_intrinsics;  // fx, fy, cx, cy [px]
uniform float u_height;     // [px] image height
uniform mat3 u_tanker_from_optical;
uniform vec3 u_camera;      // [m] camera centre in the tanker frame
uniform float u_sky;        // sky radiance
uniform float u_shade;      // Lambert shade of a level surface
uniform int u_kind;         // 1 sea, 2 terrain
uniform float u_ground_z;   // [m] ground plane z in the tanker frame
uniform float u_cloud_z;    // [m] cloud layer z in the tanker frame
uniform float u_coverage;   // [0, 1]
uniform float u_cloud_min_range;  // [m]
uniform float u_visibility;       // [m]
layout(location = 0) out float out_intensity;
layout(location = 1) out uint out_label;
layout(location = 2) out float out_depth;

// 2-D lattice hash (lowbias32 of a linear mix): cheaper than PCG3D, which cost a third of the speed.
float Lattice(ivec2 i, uint salt) {
  uint h = uint(i.x) * 0x8da6b343u ^ uint(i.y) * 0xd8163841u ^ salt * 0xcb1ab31fu;
  h ^= h >> 16u; h *= 0x7feb352du; h ^= h >> 15u; h *= 0x846ca68bu; h ^= h >> 16u;
  return float(h & 0xffffu) / 65535.0;
}
float ValueNoise(vec2 p, uint salt) {
  ivec2 i = ivec2(floor(p));
  vec2 f = fract(p);
  vec2 s = f * f * (3.0 - 2.0 * f);
  return mix(mix(Lattice(i, salt), Lattice(i + ivec2(1, 0), salt), s.x),
             mix(Lattice(i + ivec2(0, 1), salt), Lattice(i + ivec2(1, 1), salt), s.x), s.y);
}
float Visible(float size, float footprint) { return 1.0 - smoothstep(0.5 * size, 1.5 * size, footprint); }
// Zero-mean fbm: octaves of size base / 3^i, each faded out once it is below a pixel.
float Fbm(vec2 p, float base, int octaves, float footprint, uint salt) {
  float sum = 0.0, amp = 0.5, size = base;
  for (int i = 0; i < octaves; ++i) {
    if (footprint >= 1.5 * size) break;  // this and all finer octaves are below a pixel
    sum += amp * (ValueNoise(p / size, salt + uint(i)) - 0.5) * Visible(size, footprint);
    amp *= 0.6;
    size /= 3.0;
  }
  return sum;
}

void main() {
  float u = gl_FragCoord.x - 0.5, v = u_height - 0.5 - gl_FragCoord.y;
  vec3 d = u_tanker_from_optical * vec3((u - u_intrinsics.z) / u_intrinsics.x,
                                        (v - u_intrinsics.w) / u_intrinsics.y, 1.0);
  // Ray parameters (= optical z, as the ray's optical z is 1); clamped above the horizon so that
  // the derivatives below are taken in uniform control flow.
  float dz = min(d.z, -1e-6);
  float t_ground = (u_ground_z - u_camera.z) / dz;
  float t_cloud = (u_cloud_z - u_camera.z) / dz;
  vec2 g = u_camera.xy + t_ground * d.xy;
  vec2 c = u_camera.xy + t_cloud * d.xy;
  float foot_g = max(length(fwidth(g)), 1e-3);  // [m] per pixel
  float foot_c = max(length(fwidth(c)), 1e-3);
  if (d.z >= -1e-6) {  // above the horizon: empty sky
    out_intensity = u_sky;
    out_label = 0u;
    out_depth = 0.0;
    return;
  }
  float albedo;
  if (u_kind == 1) {  // sea: dark, swell along y and wind ripples
    albedo = 0.16 + 0.5 * Fbm(vec2(g.x, 2.5 * g.y), 400.0, 6, foot_g, 31u);
  } else {  // terrain: fields and forest patches over large-scale relief shading
    albedo = 0.34 + 0.55 * Fbm(g, 4000.0, 7, foot_g, 17u);
  }
  float len = length(d);
  float haze_g = exp(-t_ground * len / u_visibility);
  float ground = mix(u_sky, clamp(albedo, 0.02, 0.9) * u_shade, haze_g);

  float alpha = 0.0;
  if (u_coverage > 0.0) {
    float density = Fbm(c, 6000.0, 5, foot_c, 53u) + 0.5;  // about 0.5 +- 0.3
    float threshold = mix(0.85, 0.15, u_coverage);
    alpha = smoothstep(threshold - 0.05, threshold + 0.05, density) *
            smoothstep(u_cloud_min_range, 1.1 * u_cloud_min_range, length(c));
  }
  out_intensity = ground;
  if (alpha > 0.0) {
    float cloud_albedo = 0.88 + 0.4 * Fbm(c, 800.0, 4, foot_c, 71u);
    float cloud = mix(u_sky, cloud_albedo, exp(-t_cloud * len / u_visibility));
    out_intensity = mix(ground, cloud, alpha);
  }
  bool is_cloud = alpha >= 0.5;
  out_label = is_cloud ? 4u : 3u;
  out_depth = is_cloud ? t_cloud : t_ground;
}
)";

// The sun's shadow map: depth along the sun's direction, orthographic, fitted to what is drawn.
const char* kShadowVertexShader = R"(#version 450 core
layout(location = 0) in vec3 in_position;
uniform mat4 u_clip_from_object;
void main() { gl_Position = u_clip_from_object * vec4(in_position, 1.0); }
)";
const char* kShadowFragmentShader = R"(#version 450 core
void main() {}
)";

// Propellers (issue 16): a disc quad in the propeller's plane; each pixel's coverage is the
// fraction of the exposure during which some blade lies over it (blades of angular half width
// atan(chord / 2r) turning from u_angle through u_swept). Pass 0 blends the radiance by that
// coverage; pass 1 writes the label and depth where it is at least one half.
const char* kPropellerVertexShader = R"(#version 450 core
uniform mat4 u_optical_from_disc;
uniform vec4 u_projection;
uniform vec2 u_depth;
uniform float u_radius;
out vec2 v_disc;  // [m] disc y, z
out float v_depth;
const vec2 kCorner[6] = vec2[6](vec2(-1, -1), vec2(1, -1), vec2(1, 1), vec2(-1, -1), vec2(1, 1),
                                vec2(-1, 1));
void main() {
  v_disc = u_radius * kCorner[gl_VertexID];
  vec3 p = (u_optical_from_disc * vec4(0.0, v_disc, 1.0)).xyz;
  v_depth = p.z;
  gl_Position = vec4(u_projection.x * p.x + u_projection.y * p.z,
                     -u_projection.z * p.y + u_projection.w * p.z,
                     u_depth.x * p.z + u_depth.y, p.z);
}
)";
const char* kPropellerFragmentShader = R"(#version 450 core
in vec2 v_disc;
in float v_depth;
uniform float u_radius, u_hub, u_half_chord, u_angle, u_swept;
uniform int u_blades;
uniform vec2 u_blade;  // radiance of the blade and of its painted tip
uniform int u_pass;
layout(location = 0) out vec4 out_color;
layout(location = 1) out uint out_label;
layout(location = 2) out float out_depth;
const float kTwoPi = 6.28318530718;
void main() {
  float r = length(v_disc);
  if (r > u_radius || r < u_hub) discard;
  float period = kTwoPi / float(u_blades);
  float a = atan(u_half_chord, r);
  float d = mod(atan(v_disc.y, v_disc.x) - u_angle, period);  // behind blade 0's start, [0, period)
  float cover;
  if (u_swept <= 1e-6) {
    cover = min(d, period - d) < a ? 1.0 : 0.0;
  } else if (u_swept >= kTwoPi) {
    cover = min(2.0 * a / period, 1.0);
  } else {  // the blade centres sweep [0, u_swept]: covered while within a of d + m period
    float total = 0.0;
    for (int m = -1; m < 64; ++m) {
      float c = d + float(m) * period;
      if (c - a > u_swept) break;
      total += max(0.0, min(c + a, u_swept) - max(c - a, 0.0));
    }
    cover = min(total / u_swept, 1.0);
  }
  if (cover <= 0.0 || (u_pass == 1 && cover < 0.5)) discard;
  out_color = vec4(r > u_radius - 0.12 ? u_blade.y : u_blade.x, 0.0, 0.0, cover);
  out_label = 5u;
  out_depth = v_depth;
}
)";

struct Mesh {
  GLuint vao = 0, vbo = 0;
  GLsizei vertices = 0;
  Label label;
  Surface surface;
  Eigen::AlignedBox3d box;    // object frame
  Eigen::AlignedBox3d glass;  // object frame: windscreen (empty: none)
};

// The same shader source with SUN defined: a program of its own, so that the ideal world's
// program stays the one whose images the tests compare bit for bit.
std::string WithSun(const char* source) {
  std::string s(source);
  const std::string version = "#version 450 core\n";
  return version + "#define SUN 1\n" + s.substr(version.size());
}

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

GLuint Link(const char* vertex, const char* fragment) {
  const GLuint vs = Compile(GL_VERTEX_SHADER, vertex);
  const GLuint fs = Compile(GL_FRAGMENT_SHADER, fragment);
  const GLuint program = glCreateProgram();
  glAttachShader(program, vs);
  glAttachShader(program, fs);
  glLinkProgram(program);
  GLint linked = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &linked);
  glDeleteShader(vs);
  glDeleteShader(fs);
  if (!linked) throw RenderError("shader program does not link");
  return program;
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
  GLuint background_program = 0, background_vao = 0;  // 0 without a background
  GLuint sun_program = 0;                             // 0 without the sun
  GLuint shadow_program = 0, shadow_framebuffer = 0, shadow_map = 0;
  std::vector<DrawItem> shadow_items;  // what the shadow map shows (valid while shadow_valid)
  bool shadow_valid = false;
  Eigen::Matrix4d shadow_clip_from_tanker = Eigen::Matrix4d::Identity();
  GLuint propeller_program = 0, empty_vao = 0;
  // The background pass's output per camera pose: it is fixed in the tanker frame, as the
  // cameras are, so each frame copies it instead of drawing it again (a rig's two cameras).
  struct CachedBackground {
    Eigen::Matrix4d T_tanker_optical;
    GLuint framebuffer = 0;
    GLuint color[3] = {0, 0, 0};
  };
  std::vector<CachedBackground> backgrounds;
  GLuint color[3] = {0, 0, 0};  // radiance R32F, label R8UI, depth R32F
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
  const SceneOptions& sc = options_.scene;
  if (sc.background != Background::kNone) {
    if (!(sc.background_altitude_m > 0.0)) throw RenderError("background_altitude must be > 0");
    if (!(sc.visibility_m > 0.0)) throw RenderError("visibility must be > 0");
    if (!(sc.cloud_coverage >= 0.0 && sc.cloud_coverage <= 1.0))
      throw RenderError("cloud_coverage must be in [0, 1]");
    if (!(sc.cloud_altitude_m > 0.0 && sc.cloud_altitude_m < sc.background_altitude_m))
      throw RenderError("cloud_altitude must be > 0 and below background_altitude");
    if (!(sc.cloud_min_range_m >= 0.0)) throw RenderError("cloud_min_range must not be negative");
  }
  if (options_.sun.enabled) options_.sun.Validate();
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

  gl_->program = Link(kVertexShader, kFragmentShader);
  if (options_.scene.background != Background::kNone) {
    gl_->background_program = Link(kBackgroundVertexShader, kBackgroundFragmentShader);
    glGenVertexArrays(1, &gl_->background_vao);
  }
  gl_->propeller_program = Link(kPropellerVertexShader, kPropellerFragmentShader);
  glGenVertexArrays(1, &gl_->empty_vao);
  if (options_.sun.enabled) {
    gl_->sun_program = Link(WithSun(kVertexShader).c_str(), WithSun(kFragmentShader).c_str());
    // The shadow map: a depth texture compared in the shader (sampler2DShadow); outside it, lit.
    const int size = options_.sun.shadow_map_size;
    gl_->shadow_program = Link(kShadowVertexShader, kShadowFragmentShader);
    glGenTextures(1, &gl_->shadow_map);
    glBindTexture(GL_TEXTURE_2D, gl_->shadow_map);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_DEPTH_COMPONENT32F, size, size);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_BORDER);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_BORDER);
    const float far_border[4] = {1, 1, 1, 1};
    glTexParameterfv(GL_TEXTURE_2D, GL_TEXTURE_BORDER_COLOR, far_border);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    glGenFramebuffers(1, &gl_->shadow_framebuffer);
    glBindFramebuffer(GL_FRAMEBUFFER, gl_->shadow_framebuffer);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, gl_->shadow_map, 0);
    glDrawBuffer(GL_NONE);
    glReadBuffer(GL_NONE);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw RenderError("the sun's shadow-map framebuffer is incomplete");
  }

  glGenFramebuffers(1, &gl_->framebuffer);
  glBindFramebuffer(GL_FRAMEBUFFER, gl_->framebuffer);
  glGenRenderbuffers(3, gl_->color);
  // Radiance in float: the sensor model (sensor.h) makes the grey levels.
  const GLenum formats[3] = {GL_R32F, GL_R8UI, GL_R32F};
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
    glDeleteProgram(gl_->propeller_program);
    glDeleteVertexArrays(1, &gl_->empty_vao);
    if (gl_->sun_program) {
      glDeleteProgram(gl_->sun_program);
      glDeleteProgram(gl_->shadow_program);
      glDeleteFramebuffers(1, &gl_->shadow_framebuffer);
      glDeleteTextures(1, &gl_->shadow_map);
    }
    if (gl_->background_program) glDeleteProgram(gl_->background_program);
    for (const auto& b : gl_->backgrounds) {
      glDeleteRenderbuffers(3, b.color);
      glDeleteFramebuffers(1, &b.framebuffer);
    }
    if (gl_->background_vao) glDeleteVertexArrays(1, &gl_->background_vao);
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

Image<uint8_t> Renderer::ConvertLikeR8Attachment(const Image<float>& radiance) {
  static const char* kVertex = R"(#version 450 core
void main() {  // one triangle over the whole viewport
  gl_Position = vec4(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0, 0.0, 1.0);
}
)";
  static const char* kFragment = R"(#version 450 core
uniform sampler2D u_radiance;
layout(location = 0) out float out_intensity;
void main() { out_intensity = texelFetch(u_radiance, ivec2(gl_FragCoord.xy), 0).r; }
)";
  CurrentContext current(*gl_);
  const int w = radiance.width, h = radiance.height;
  const GLuint vs = Compile(GL_VERTEX_SHADER, kVertex), fs = Compile(GL_FRAGMENT_SHADER, kFragment);
  const GLuint program = glCreateProgram();
  glAttachShader(program, vs);
  glAttachShader(program, fs);
  glLinkProgram(program);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLuint texture = 0, framebuffer = 0, color = 0, vao = 0;
  glGenTextures(1, &texture);
  glBindTexture(GL_TEXTURE_2D, texture);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);  // complete without mipmaps
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_R32F, w, h, 0, GL_RED, GL_FLOAT, radiance.data.data());
  glGenFramebuffers(1, &framebuffer);
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
  glGenRenderbuffers(1, &color);
  glBindRenderbuffer(GL_RENDERBUFFER, color);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_R8, w, h);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color);
  glGenVertexArrays(1, &vao);
  glBindVertexArray(vao);
  glViewport(0, 0, w, h);
  glDisable(GL_DEPTH_TEST);
  glUseProgram(program);
  glUniform1i(glGetUniformLocation(program, "u_radiance"), 0);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  Image<uint8_t> out;
  out.width = w;
  out.height = h;
  out.data.resize(radiance.data.size());
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glReadPixels(0, 0, w, h, GL_RED, GL_UNSIGNED_BYTE, out.data.data());
  // Back to the renderer's state (Render binds its own framebuffer and program).
  glBindVertexArray(0);
  glEnable(GL_DEPTH_TEST);
  glViewport(0, 0, options_.intrinsics.width, options_.intrinsics.height);
  glDeleteVertexArrays(1, &vao);
  glDeleteRenderbuffers(1, &color);
  glDeleteFramebuffers(1, &framebuffer);
  glDeleteTextures(1, &texture);
  glDeleteProgram(program);
  CheckGl("8-bit conversion");
  return out;
}

int Renderer::AddMesh(const aar_geometry::TriangleMesh& mesh, Label label, Surface surface,
                      const Eigen::AlignedBox3d& glass) {
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
  m.glass = glass;
  for (const Eigen::Vector3d& p : mesh.vertices) m.box.extend(p);
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

void Renderer::CopyBackground(const Eigen::Isometry3d& T_tanker_optical) {
  const CameraIntrinsics& k = options_.intrinsics;
  auto& cache = gl_->backgrounds;
  auto it = std::find_if(cache.begin(), cache.end(), [&](const Gl::CachedBackground& b) {
    return b.T_tanker_optical == T_tanker_optical.matrix();
  });
  if (it == cache.end()) {
    if (cache.size() >= 4) {  // a camera that moves: keep the newest few
      glDeleteRenderbuffers(3, cache.front().color);
      glDeleteFramebuffers(1, &cache.front().framebuffer);
      cache.erase(cache.begin());
    }
    Gl::CachedBackground b;
    b.T_tanker_optical = T_tanker_optical.matrix();
    glGenFramebuffers(1, &b.framebuffer);
    glBindFramebuffer(GL_FRAMEBUFFER, b.framebuffer);
    glGenRenderbuffers(3, b.color);
    const GLenum formats[3] = {GL_R32F, GL_R8UI, GL_R32F};
    for (int i = 0; i < 3; ++i) {
      glBindRenderbuffer(GL_RENDERBUFFER, b.color[i]);
      glRenderbufferStorage(GL_RENDERBUFFER, formats[i], k.width, k.height);
      glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + i, GL_RENDERBUFFER,
                                b.color[i]);
    }
    const GLenum buffers[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
    glDrawBuffers(3, buffers);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw RenderError("the background cache's framebuffer is incomplete");
    DrawBackground(T_tanker_optical);  // covers every pixel (the sky above the horizon too)
    glBindFramebuffer(GL_FRAMEBUFFER, gl_->framebuffer);
    cache.push_back(b);
    it = cache.end() - 1;
  }
  for (int i = 0; i < 3; ++i) {
    glCopyImageSubData(it->color[i], GL_RENDERBUFFER, 0, 0, 0, 0, gl_->color[i], GL_RENDERBUFFER, 0,
                       0, 0, 0, k.width, k.height, 1);
  }
  CheckGl("background copy");
}

void Renderer::DrawBackground(const Eigen::Isometry3d& T_tanker_optical) {
  const CameraIntrinsics& k = options_.intrinsics;
  const SceneOptions& sc = options_.scene;
  const GLuint p = gl_->background_program;
  glUseProgram(p);
  glUniform4f(glGetUniformLocation(p, "u_intrinsics"), static_cast<float>(k.fx),
              static_cast<float>(k.fy), static_cast<float>(k.cx), static_cast<float>(k.cy));
  glUniform1f(glGetUniformLocation(p, "u_height"), static_cast<float>(k.height));
  const Eigen::Matrix3f R = T_tanker_optical.linear().cast<float>();
  glUniformMatrix3fv(glGetUniformLocation(p, "u_tanker_from_optical"), 1, GL_FALSE, R.data());
  const Eigen::Vector3f o = T_tanker_optical.translation().cast<float>();
  glUniform3f(glGetUniformLocation(p, "u_camera"), o.x(), o.y(), o.z());
  glUniform1f(glGetUniformLocation(p, "u_sky"), static_cast<float>(options_.sky_level / 255.0));
  // The mesh shader's shade of a level surface facing up, so ground and aircraft match.
  const SunOptions& sun = options_.sun;
  const double up =
      sun.enabled ? sun.DirectionInTanker().z() : std::abs(options_.sun_in_tanker.normalized().z());
  const double shade = sun.enabled ? sun.ambient + sun.direct * up : 0.45 + 0.55 * up;
  glUniform1f(glGetUniformLocation(p, "u_shade"), static_cast<float>(shade));
  glUniform1i(glGetUniformLocation(p, "u_kind"), static_cast<int>(sc.background));
  glUniform1f(glGetUniformLocation(p, "u_ground_z"), static_cast<float>(-sc.background_altitude_m));
  glUniform1f(glGetUniformLocation(p, "u_cloud_z"), static_cast<float>(-sc.cloud_altitude_m));
  glUniform1f(glGetUniformLocation(p, "u_coverage"), static_cast<float>(sc.cloud_coverage));
  glUniform1f(glGetUniformLocation(p, "u_cloud_min_range"),
              static_cast<float>(sc.cloud_min_range_m));
  glUniform1f(glGetUniformLocation(p, "u_visibility"), static_cast<float>(sc.visibility_m));
  glDepthMask(GL_FALSE);
  glBindVertexArray(gl_->background_vao);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glDepthMask(GL_TRUE);
}

RenderedView Renderer::Render(const Eigen::Isometry3d& T_tanker_optical,
                              const std::vector<DrawItem>& items, bool want_label, bool want_depth,
                              const std::vector<PropellerItem>& propellers) {
  const CameraIntrinsics& k = options_.intrinsics;
  CurrentContext current(*gl_);
  const SunOptions& sun_options = options_.sun;
  const bool sun = sun_options.enabled;
  const Eigen::Matrix4d shadow_clip_from_tanker =
      sun && sun_options.shadows ? UpdateShadowMap(items) : Eigen::Matrix4d::Identity();
  glBindFramebuffer(GL_FRAMEBUFFER, gl_->framebuffer);
  glViewport(0, 0, k.width, k.height);
  const float sky[4] = {static_cast<float>(options_.sky_level / 255.0), 0, 0, 0};
  const GLuint background[4] = {static_cast<GLuint>(Label::kBackground), 0, 0, 0};
  const float no_depth[4] = {0, 0, 0, 0};
  glClearBufferfv(GL_COLOR, 0, sky);
  glClearBufferuiv(GL_COLOR, 1, background);
  glClearBufferfv(GL_COLOR, 2, no_depth);
  glClear(GL_DEPTH_BUFFER_BIT);
  if (gl_->background_program) CopyBackground(T_tanker_optical);

  const GLuint program = sun ? gl_->sun_program : gl_->program;
  glUseProgram(program);
  const GLint u_optical = glGetUniformLocation(program, "u_optical_from_object");
  const GLint u_tanker = glGetUniformLocation(program, "u_tanker_from_object");
  const GLint u_label = glGetUniformLocation(program, "u_label");
  const GLint u_surface = glGetUniformLocation(program, "u_surface");
  const GLint u_tanker_offset = glGetUniformLocation(program, "u_tanker_offset");
  const GLint u_sun_from_object = glGetUniformLocation(program, "u_sun_from_object");
  const GLint u_glass_min = glGetUniformLocation(program, "u_glass_min");
  const GLint u_glass_max = glGetUniformLocation(program, "u_glass_max");
  // Pixel centres: image column u maps to window x = u + 0.5; rows are flipped on read-back.
  glUniform4f(glGetUniformLocation(program, "u_projection"),
              static_cast<float>(2.0 * k.fx / k.width),
              static_cast<float>(2.0 * (k.cx + 0.5) / k.width - 1.0),
              static_cast<float>(2.0 * k.fy / k.height),
              static_cast<float>(1.0 - 2.0 * (k.cy + 0.5) / k.height));
  const double n = options_.near_m, f = options_.far_m;
  glUniform2f(glGetUniformLocation(program, "u_depth"), static_cast<float>((f + n) / (f - n)),
              static_cast<float>(-2.0 * f * n / (f - n)));
  const Eigen::Vector3f light =
      (sun ? sun_options.DirectionInTanker() : options_.sun_in_tanker.normalized()).cast<float>();
  glUniform3f(glGetUniformLocation(program, "u_sun"), light.x(), light.y(), light.z());
  if (sun) {
    const Eigen::Vector3f c = T_tanker_optical.translation().cast<float>();
    glUniform3f(glGetUniformLocation(program, "u_camera"), c.x(), c.y(), c.z());
    glUniform1f(glGetUniformLocation(program, "u_direct"), static_cast<float>(sun_options.direct));
    glUniform1f(glGetUniformLocation(program, "u_ambient"),
                static_cast<float>(sun_options.ambient));
    glUniform3f(glGetUniformLocation(program, "u_specular"),
                static_cast<float>(sun_options.paint_specular),
                static_cast<float>(sun_options.metal_specular),
                static_cast<float>(sun_options.glass_specular));
    glUniform1i(glGetUniformLocation(program, "u_shadows"), sun_options.shadows ? 1 : 0);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, gl_->shadow_map);
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
    if (sun) {
      // An empty box (min above max) makes no glass.
      Eigen::Vector3f lo = Eigen::Vector3f::Constant(1e9f), hi = Eigen::Vector3f::Constant(-1e9f);
      if (!m.glass.isEmpty()) lo = m.glass.min().cast<float>(), hi = m.glass.max().cast<float>();
      glUniform3f(u_glass_min, lo.x(), lo.y(), lo.z());
      glUniform3f(u_glass_max, hi.x(), hi.y(), hi.z());
      const Eigen::Vector3f offset = item.T_tanker_object.translation().cast<float>();
      glUniform3f(u_tanker_offset, offset.x(), offset.y(), offset.z());
      const Eigen::Matrix4f sun_from_object =
          (shadow_clip_from_tanker * item.T_tanker_object.matrix()).cast<float>();
      glUniformMatrix4fv(u_sun_from_object, 1, GL_FALSE, sun_from_object.data());
    }
    glUniform1i(u_label, static_cast<int>(m.label));
    glUniform1i(u_surface, static_cast<int>(m.surface));
    glBindVertexArray(m.vao);
    glDrawArrays(GL_TRIANGLES, 0, m.vertices);
  }
  glBindVertexArray(0);
  if (!propellers.empty()) DrawPropellers(T_tanker_optical, propellers);

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
  read(GL_COLOR_ATTACHMENT0, GL_RED, GL_FLOAT, view.radiance);
  if (want_label) read(GL_COLOR_ATTACHMENT1, GL_RED_INTEGER, GL_UNSIGNED_BYTE, view.label);
  if (want_depth) read(GL_COLOR_ATTACHMENT2, GL_RED, GL_FLOAT, view.depth);
  CheckGl("render");
  return view;
}

Eigen::Matrix4d Renderer::UpdateShadowMap(const std::vector<DrawItem>& items) {
  auto same = [](const DrawItem& a, const DrawItem& b) {
    return a.mesh == b.mesh && a.T_tanker_object.matrix() == b.T_tanker_object.matrix();
  };
  if (gl_->shadow_valid && items.size() == gl_->shadow_items.size() &&
      std::equal(items.begin(), items.end(), gl_->shadow_items.begin(), same)) {
    return gl_->shadow_clip_from_tanker;  // the other camera of the pair
  }
  // The sun's frame: z towards the sun, x and y across; fitted to the boxes of what is drawn.
  const Eigen::Vector3d s = options_.sun.DirectionInTanker();
  const Eigen::Vector3d any =
      std::abs(s.z()) < 0.9 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitX();
  const Eigen::Vector3d x = any.cross(s).normalized(), y = s.cross(x);
  Eigen::Matrix3d R_sun_tanker;
  R_sun_tanker << x.transpose(), y.transpose(), s.transpose();
  Eigen::AlignedBox3d bounds;
  for (const DrawItem& item : items) {
    if (item.mesh < 0 || item.mesh >= static_cast<int>(gl_->meshes.size())) {
      throw RenderError("draw item refers to mesh " + std::to_string(item.mesh));
    }
    const Eigen::AlignedBox3d& box = gl_->meshes[item.mesh].box;
    for (int c = 0; c < 8; ++c) {
      bounds.extend(R_sun_tanker * (item.T_tanker_object *
                                    box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c))));
    }
  }
  if (bounds.isEmpty()) bounds.extend(Eigen::Vector3d::Zero());
  bounds.min() -= Eigen::Vector3d(0.5, 0.5, 1.0);  // [m] margins
  bounds.max() += Eigen::Vector3d(0.5, 0.5, 1.0);
  const Eigen::Vector3d lo = bounds.min(), size = bounds.sizes();
  const double extent = std::max(size.x(), size.y());  // square texels
  // x, y -> [-1, 1]; the sun's z (larger: nearer the sun) -> depth -1 (near) .. 1 (far).
  Eigen::Matrix4d clip_from_sun = Eigen::Matrix4d::Identity();
  clip_from_sun(0, 0) = 2.0 / extent;
  clip_from_sun(0, 3) = -1.0 - 2.0 * lo.x() / extent;
  clip_from_sun(1, 1) = 2.0 / extent;
  clip_from_sun(1, 3) = -1.0 - 2.0 * lo.y() / extent;
  clip_from_sun(2, 2) = -2.0 / size.z();
  clip_from_sun(2, 3) = 1.0 + 2.0 * lo.z() / size.z();
  Eigen::Matrix4d sun_from_tanker = Eigen::Matrix4d::Identity();
  sun_from_tanker.topLeftCorner<3, 3>() = R_sun_tanker;
  const Eigen::Matrix4d clip_from_tanker = clip_from_sun * sun_from_tanker;

  const int map = options_.sun.shadow_map_size;
  glBindFramebuffer(GL_FRAMEBUFFER, gl_->shadow_framebuffer);
  glViewport(0, 0, map, map);
  glClear(GL_DEPTH_BUFFER_BIT);
  glUseProgram(gl_->shadow_program);
  const GLint u_clip = glGetUniformLocation(gl_->shadow_program, "u_clip_from_object");
  glEnable(GL_POLYGON_OFFSET_FILL);
  glPolygonOffset(1.0f, 2.0f);
  for (const DrawItem& item : items) {
    const Eigen::Matrix4f clip_from_object =
        (clip_from_tanker * item.T_tanker_object.matrix()).cast<float>();
    glUniformMatrix4fv(u_clip, 1, GL_FALSE, clip_from_object.data());
    const Mesh& m = gl_->meshes[item.mesh];
    glBindVertexArray(m.vao);
    glDrawArrays(GL_TRIANGLES, 0, m.vertices);
  }
  glBindVertexArray(0);
  glDisable(GL_POLYGON_OFFSET_FILL);
  CheckGl("shadow map");
  gl_->shadow_items = items;
  gl_->shadow_clip_from_tanker = clip_from_tanker;
  gl_->shadow_valid = true;
  return clip_from_tanker;
}

void Renderer::DrawPropellers(const Eigen::Isometry3d& T_tanker_optical,
                              const std::vector<PropellerItem>& propellers) {
  const CameraIntrinsics& k = options_.intrinsics;
  const GLuint p = gl_->propeller_program;
  glUseProgram(p);
  glUniform4f(glGetUniformLocation(p, "u_projection"), static_cast<float>(2.0 * k.fx / k.width),
              static_cast<float>(2.0 * (k.cx + 0.5) / k.width - 1.0),
              static_cast<float>(2.0 * k.fy / k.height),
              static_cast<float>(1.0 - 2.0 * (k.cy + 0.5) / k.height));
  const double n = options_.near_m, f = options_.far_m;
  glUniform2f(glGetUniformLocation(p, "u_depth"), static_cast<float>((f + n) / (f - n)),
              static_cast<float>(-2.0 * f * n / (f - n)));
  const Eigen::Isometry3d T_optical_tanker = T_tanker_optical.inverse();
  glBindVertexArray(gl_->empty_vao);
  glDepthMask(GL_FALSE);  // translucent: what lies behind stays in the depth buffer
  for (const PropellerItem& prop : propellers) {
    if (!(prop.radius_m > prop.hub_radius_m && prop.hub_radius_m >= 0.0 && prop.chord_m > 0.0 &&
          prop.blades > 0 && prop.swept_rad >= 0.0)) {
      throw RenderError(
          "a propeller needs radius > hub radius >= 0, chord > 0, blades > 0 and a "
          "non-negative sweep");
    }
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
    const SunOptions& sun = options_.sun;
    const double facing = std::abs(
        axis.dot(sun.enabled ? sun.DirectionInTanker() : options_.sun_in_tanker.normalized()));
    const double shade = sun.enabled ? sun.ambient + sun.direct * facing : 0.45 + 0.55 * facing;
    glUniform2f(glGetUniformLocation(p, "u_blade"), static_cast<float>(0.08 * shade),
                static_cast<float>(0.85 * shade));
    // Pass 0: the radiance, blended by coverage; pass 1: label and depth where covered most.
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
  glDepthMask(GL_TRUE);
  glBindVertexArray(0);
}

Eigen::Vector3d SunOptions::DirectionInTanker() const {
  const double az = azimuth_deg * M_PI / 180.0, el = elevation_deg * M_PI / 180.0;
  // Bearing clockwise seen from above: towards the right wing is -y in the tanker frame.
  return {std::cos(el) * std::cos(az), -std::cos(el) * std::sin(az), std::sin(el)};
}

void SunOptions::Validate() const {
  auto check = [](bool ok, const char* key, const std::string& what) {
    if (!ok) throw std::invalid_argument(std::string(key) + " " + what);
  };
  check(elevation_deg > 0.0 && elevation_deg <= 90.0, "sun_elevation_deg",
        "must be in (0, 90]: a sun at or below the horizon lights nothing from above (got " +
            std::to_string(elevation_deg) + ")");
  check(std::isfinite(azimuth_deg), "sun_azimuth_deg", "must be a finite angle");
  check(direct > 0.0 && direct <= 4.0, "sun_direct", "must be in (0, 4]");
  check(ambient >= 0.0 && ambient <= 2.0, "sun_ambient", "must be in [0, 2]");
  check(shadow_map_size >= 64 && shadow_map_size <= 8192, "sun_shadow_map_size",
        "must be from 64 to 8192 texels");
  check(paint_specular >= 0.0, "sun_paint_specular", "must not be negative");
  check(metal_specular >= 0.0, "sun_metal_specular", "must not be negative");
  check(glass_specular >= 0.0, "sun_glass_specular", "must not be negative");
}

}  // namespace aar_sim
