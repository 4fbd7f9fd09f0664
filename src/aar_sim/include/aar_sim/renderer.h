#pragma once

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <aar_geometry/triangle_mesh.h>

#include "aar_sim/camera.h"

namespace aar_sim {

// No usable EGL display or OpenGL 4.5 context (or a GL call failed).
class RenderError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

template <typename T>
struct Image {
  int width = 0;
  int height = 0;
  std::vector<T> data;  // row-major, row 0 at the top

  T& at(int u, int v) { return data[static_cast<size_t>(v) * width + u]; }
  const T& at(int u, int v) const { return data[static_cast<size_t>(v) * width + u]; }
};

// Per-pixel class in the label image.
// kBackground is empty sky; kGround and kCloud come from the background pass, kPropeller from a
// propeller's blades where they cover the pixel for at least half the exposure (issue 16).
enum class Label : uint8_t {
  kBackground = 0,
  kReceiver = 1,
  kBoom = 2,
  kGround = 3,
  kCloud = 4,
  kPropeller = 5
};
// Procedural surface appearance. kAircraftPaint's triangles may be marked as glass (AddMesh).
enum class Surface { kAircraftPaint = 0, kBoomStripes = 1 };
// What lies below the tanker (docs/realism/scene.md). kNone: today's plain sky.
enum class Background { kNone = 0, kSea = 1, kTerrain = 2 };

// Scene: background (issue 16). Defaults = the ideal world (plain sky, no background pass).
// The ground is a plane `background_altitude_m` below the tanker frame's origin, textured in
// tanker x/y; the cloud layer is a plane `cloud_altitude_m` below the tanker, drawn only beyond
// `cloud_min_range_m` (horizontal, from the tanker's origin).
struct SceneOptions {
  Background background = Background::kNone;
  double background_altitude_m = 3000.0;  // [m] ground/sea below the tanker (> 0)
  double visibility_m = 30000.0;          // [m] haze: radiance blends to the sky by exp(-d/vis)
  double cloud_coverage = 0.0;            // [0, 1] fraction of the layer covered; 0 = no clouds
  double cloud_altitude_m = 1500.0;       // [m] cloud layer below the tanker (> 0, < ground)
  double cloud_min_range_m = 1000.0;      // [m] no cloud nearer than this (horizontal)
};

// The sun (issue 16, docs/realism/sun.md): direct light from a direction, skylight, cast shadows
// (a shadow map of everything drawn: the boom's shadow on the receiver, the receiver's on itself)
// and specular glare on paint, metal and glass. Off (the default): the thesis's fixed, shadowless
// light from RendererOptions::sun_in_tanker, images bit-identical to those before the sun existed.
struct SunOptions {
  bool enabled = false;
  double azimuth_deg = 30.0;     // [deg] bearing from the tanker's nose, positive to its right wing
  double elevation_deg = 60.0;   // [deg] above the horizon, in (0, 90]
  double direct = 0.8;           // radiance of a white surface square to the sun (1 = grey 255)
  double ambient = 0.25;         // skylight on every surface, lit or not (same scale)
  bool shadows = true;           // cast shadows
  int shadow_map_size = 1024;    // [texels] per side, fitted to what is drawn: ~a pixel at contact
  double paint_specular = 0.15;  // peak glare as a fraction of `direct`: painted surfaces,
  double metal_specular = 0.6;   //   the boom's bare metal,
  double glass_specular = 2.0;   //   windscreen glass (above 1: clips to white)

  Eigen::Vector3d DirectionInTanker() const;  // unit, towards the sun
  // Throws std::invalid_argument naming the field that is out of range (sun_elevation <= 0: the
  // sun below the horizon, say).
  void Validate() const;
};

// A spinning propeller at the shutter (issue 16): a disc in the plane x = 0 of its frame (x: the
// thrust axis), drawn after the opaque meshes and blended over them by the fraction of the
// exposure its blades cover each pixel. swept_rad = 0: blades frozen at angle_rad; 2 pi or more:
// the fully blurred disc.
struct PropellerItem {
  Eigen::Isometry3d T_tanker_disc = Eigen::Isometry3d::Identity();
  double radius_m = 1.25;      // [m] blade tip
  double hub_radius_m = 0.15;  // [m] spinner: no blade inside it
  double chord_m = 0.18;       // [m] blade width
  int blades = 4;
  double angle_rad = 0.0;  // blade 0 at the exposure's start, about x from the disc's y towards z
  double swept_rad = 0.0;  // [rad] the blades' turn during the exposure
};

struct RendererOptions {
  CameraIntrinsics intrinsics;
  double near_m = 0.5;                           // [m] clip planes
  double far_m = 2000.0;                         // [m]
  double sky_level = 200.0;                      // [grey level] plain, texture-free sky
  Eigen::Vector3d sun_in_tanker{0.3, 0.2, 1.0};  // the ideal world's light (sun.enabled false)
  SceneOptions scene;
  SunOptions sun;
};

struct RenderedView {
  Image<float> radiance;  // linear, 1.0 = grey level 255 of the ideal sensor (may exceed 1)
  Image<uint8_t> image;   // mono8: the sensor's output (World; the renderer leaves it empty)
  Image<uint8_t> label;   // Label per pixel (when requested)
  Image<float> depth;     // [m] optical z per pixel, 0 for empty sky (when requested)
};

struct DrawItem {
  int mesh = 0;  // from Renderer::AddMesh
  Eigen::Isometry3d T_tanker_object = Eigen::Isometry3d::Identity();
};

// Offscreen OpenGL 4.5 renderer through EGL: a GPU's EGL device where there is one, else Mesa's
// surfaceless platform (llvmpipe), with no display server. Deterministic: the same inputs give
// bit-identical images. Not thread-safe, but not tied to a thread: each call binds the context
// on the caller's thread and releases it. The GLSL is read at construction from the package's
// shaders/ directory (installed with it; the environment variable AAR_SIM_SHADER_DIR overrides
// where it is looked for); a missing file is a RenderError naming it.
class Renderer {
 public:
  explicit Renderer(const RendererOptions& options);  // throws RenderError
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Uploads a mesh (in its object frame); returns its handle. `glass`: where the surface is
  // windscreen glass (dark, glossy: the sun's glare), in the object frame: the part of the surface
  // inside the box whose normal points up (z > 0.2); empty = none.
  int AddMesh(const aar_geometry::TriangleMesh& mesh, Label label, Surface surface,
              const Eigen::AlignedBox3d& glass = Eigen::AlignedBox3d());

  // Renders the items seen from a camera at T_tanker_optical: the radiance, and the label and
  // depth when asked for; then the propellers over them. The mono8 image is the sensor model's
  // (sensor.h). With the sun's shadows, one shadow map serves every view of the same items.
  RenderedView Render(const Eigen::Isometry3d& T_tanker_optical, const std::vector<DrawItem>& items,
                      bool want_label, bool want_depth,
                      const std::vector<PropellerItem>& propellers = {});
  // The label image alone of the items seen from T_tanker_optical: no background, no propellers,
  // no shading. What World::MeasureVisibility draws the receiver's silhouette with.
  Image<uint8_t> RenderLabel(const Eigen::Isometry3d& T_tanker_optical,
                             const std::vector<DrawItem>& items);

  const RendererOptions& options() const { return options_; }
  std::string gl_renderer() const;  // e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"

  // `radiance` as OpenGL stores it in an 8-bit normalised attachment: the mono8 image the
  // renderer gave before the sensor model (sensor.h) existed, which the ideal sensor must equal
  // bit for bit. For tests.
  Image<uint8_t> ConvertLikeR8Attachment(const Image<float>& radiance);

 public:
  struct Gl;  // EGL and OpenGL objects (src/renderer/gl_state.h), shared by the passes

 private:
  RendererOptions options_;
  std::unique_ptr<Gl> gl_;
};

}  // namespace aar_sim
