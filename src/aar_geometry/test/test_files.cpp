#include "test_files.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include <gtest/gtest.h>

#include "aar_geometry/load_error.h"
#include "aar_geometry/primitives.h"

namespace aar_geometry::test {

TempDir::TempDir() {
  const char* tmp = std::getenv("TMPDIR");
  std::string pattern = std::string(tmp ? tmp : "/tmp") + "/aar_geometry_test_XXXXXX";
  if (::mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("mkdtemp failed");
  path_ = pattern;
}

TempDir::~TempDir() {
  std::error_code ec;
  std::filesystem::remove_all(path_, ec);
}

std::string TempDir::Write(const std::string& name, const std::string& contents) const {
  const std::string path = Path(name);
  std::ofstream out(path, std::ios::binary);
  out.write(contents.data(), static_cast<std::streamsize>(contents.size()));
  if (!out) throw std::runtime_error("cannot write " + path);
  return path;
}

std::string DataPath(const std::string& name) {
  return std::string(AAR_GEOMETRY_TEST_DATA) + "/" + name;
}

TriangleMesh UnsharedCube() {
  const TriangleMesh shared = MakeBox({1.0, 1.0, 1.0});
  TriangleMesh out;
  out.AddPart("cube");
  for (const auto& t : shared.triangles) {
    const int base = static_cast<int>(out.vertices.size());
    for (int k = 0; k < 3; ++k) out.vertices.push_back(shared.vertices[t[k]]);
    out.triangles.emplace_back(base, base + 1, base + 2);
    out.triangle_parts.push_back(0);
  }
  return out;
}

void ExpectLoadError(const std::function<void(const std::string&)>& load, const std::string& path,
                     const std::string& fragment) {
  try {
    load(path);
    ADD_FAILURE() << "loaded " << path;
  } catch (const LoadError& e) {
    EXPECT_EQ(e.path(), path);
    EXPECT_EQ(std::string(e.what()).rfind(path + ": ", 0), 0u) << e.what();
    EXPECT_NE(e.reason().find(fragment), std::string::npos) << e.what();
  }
}

}  // namespace aar_geometry::test
