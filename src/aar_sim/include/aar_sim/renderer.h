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
// kBackground is empty sky; kGround and kCloud come from the background pass (issue 16);
// kPropeller = 5 is reserved.
enum class Label : uint8_t { kBackground = 0, kReceiver = 1, kBoom = 2, kGround = 3, kCloud = 4 };
// Procedural surface appearance.
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

struct RendererOptions {
  CameraIntrinsics intrinsics;
  double near_m = 0.5;                           // [m] clip planes
  double far_m = 2000.0;                         // [m]
  double sky_level = 200.0;                      // [grey level] plain, texture-free sky
  Eigen::Vector3d sun_in_tanker{0.3, 0.2, 1.0};  // direction towards the sun
  SceneOptions scene;
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
// on the caller's thread and releases it.
class Renderer {
 public:
  explicit Renderer(const RendererOptions& options);  // throws RenderError
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Uploads a mesh (in its object frame); returns its handle.
  int AddMesh(const aar_geometry::TriangleMesh& mesh, Label label, Surface surface);

  // Renders the items seen from a camera at T_tanker_optical: the radiance, and the label and
  // depth when asked for. The mono8 image is the sensor model's (sensor.h).
  RenderedView Render(const Eigen::Isometry3d& T_tanker_optical, const std::vector<DrawItem>& items,
                      bool want_label, bool want_depth);

  const RendererOptions& options() const { return options_; }
  std::string gl_renderer() const;  // e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"

  // `radiance` as OpenGL stores it in an 8-bit normalised attachment: the mono8 image the
  // renderer gave before the sensor model (sensor.h) existed, which the ideal sensor must equal
  // bit for bit. For tests.
  Image<uint8_t> ConvertLikeR8Attachment(const Image<float>& radiance);

 public:
  struct Gl;  // EGL and GL state (renderer.cpp)

 private:
  void DrawBackground(const Eigen::Isometry3d& T_tanker_optical);  // issue 16 background pass

  RendererOptions options_;
  std::unique_ptr<Gl> gl_;
};

}  // namespace aar_sim
