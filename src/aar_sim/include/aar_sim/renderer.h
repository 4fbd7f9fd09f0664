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
enum class Label : uint8_t { kBackground = 0, kReceiver = 1, kBoom = 2 };
// Procedural surface appearance.
enum class Surface { kAircraftPaint = 0, kBoomStripes = 1 };

struct RendererOptions {
  CameraIntrinsics intrinsics;
  double near_m = 0.5;        // [m] clip planes
  double far_m = 2000.0;      // [m]
  double sky_level = 200.0;   // [grey level] plain, texture-free sky
  double noise_stddev = 0.0;  // [grey levels] Gaussian sensor noise; 0 = none
  uint64_t noise_seed = 1;    // noise of view k of frame n depends only on (seed, n, k)
  Eigen::Vector3d sun_in_tanker{0.3, 0.2, 1.0};  // direction towards the sun
};

struct RenderedView {
  Image<uint8_t> image;  // mono8 intensity
  Image<uint8_t> label;  // Label per pixel (when requested)
  Image<float> depth;    // [m] optical z per pixel, 0 for background (when requested)
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

  // Renders the items seen from a camera at T_tanker_optical. `view_key` selects the noise
  // stream (e.g. 2 * frame + camera).
  RenderedView Render(const Eigen::Isometry3d& T_tanker_optical, const std::vector<DrawItem>& items,
                      uint64_t view_key, bool want_label, bool want_depth);

  const RendererOptions& options() const { return options_; }
  std::string gl_renderer() const;  // e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"

 public:
  struct Gl;  // EGL and GL state (renderer.cpp)

 private:
  RendererOptions options_;
  std::unique_ptr<Gl> gl_;
};

}  // namespace aar_sim
