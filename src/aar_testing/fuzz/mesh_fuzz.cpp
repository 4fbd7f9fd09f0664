// Fuzz target mesh: a mesh file through aar_geometry::LoadMesh (assimp), then what model_info
// and the occlusion stage do with a loaded mesh: weld, adjacency, closedness, convexity, bounds.
// The first byte picks the format (OBJ, PLY, STL, COLLADA: the project's), the rest is the file.
// LoadMesh may refuse a file with aar_geometry::LoadError, WeldVertices coordinates too large
// for its grid with std::invalid_argument.
#include <stdexcept>

#include <aar_geometry/adjacency.h>
#include <aar_geometry/load_error.h>
#include <aar_geometry/mesh_io.h>
#include <aar_geometry/weld.h>

#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  static const char* const kExtensions[] = {"obj", "ply", "stl", "dae"};
  const std::string file =
      aar_fuzz::WriteScratch(std::string("mesh.") + kExtensions[data[0] % 4], data + 1, size - 1);
  aar_geometry::TriangleMesh mesh;
  try {
    mesh = aar_geometry::LoadMesh(file);
  } catch (const aar_geometry::LoadError&) {
    return 0;
  }
  FUZZ_CHECK(!mesh.triangles.empty(), "a loaded mesh has triangles");
  mesh.Validate();  // LoadMesh promises a valid mesh: no exception expected
  const Eigen::AlignedBox3d bounds = mesh.Bounds();
  FUZZ_CHECK(!bounds.isEmpty(), "a mesh with triangles has bounds");
  try {
    const aar_geometry::WeldResult welded = aar_geometry::WeldVertices(mesh);
    FUZZ_CHECK(welded.mesh.triangles.size() + welded.removed_triangles == mesh.triangles.size(),
               "welding keeps or removes each triangle");
    const aar_geometry::TriangleAdjacency adjacency = aar_geometry::BuildAdjacency(welded.mesh);
    FUZZ_CHECK(adjacency.closed() == adjacency.NotClosedReason().empty(),
               "closed() and its reason agree");
    // O(triangles x vertices): as the occlusion stage, only for small parts.
    if (welded.mesh.triangles.size() <= 2000) aar_geometry::IsConvex(welded.mesh);
  } catch (const std::invalid_argument& e) {
    // WeldVertices: coordinates too large for its grid. Anything else is a finding.
    FUZZ_CHECK(std::string(e.what()).find("epsilon") != std::string::npos ||
                   std::string(e.what()).find("grid") != std::string::npos,
               e.what());
  }
  return 0;
}
