#pragma once

#include <functional>
#include <string>

#include "aar_geometry/triangle_mesh.h"

namespace aar_geometry::test {

// A fresh directory under $TMPDIR, removed with everything in it on destruction.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  std::string Path(const std::string& name) const { return path_ + "/" + name; }
  // Writes `contents` (binary-safe) to `name` and returns its path.
  std::string Write(const std::string& name, const std::string& contents) const;

 private:
  std::string path_;
};

// A committed fixture under test/data.
std::string DataPath(const std::string& name);

// Unit cube centred at the origin as six faces of two triangles each, the vertices of every
// triangle its own (36), as STL and many exporters store meshes.
TriangleMesh UnsharedCube();

// Expects `load(path)` to throw LoadError for `path` whose message names the file and contains
// `fragment`.
void ExpectLoadError(const std::function<void(const std::string&)>& load, const std::string& path,
                     const std::string& fragment);

}  // namespace aar_geometry::test
