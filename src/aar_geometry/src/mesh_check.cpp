#include "mesh_check.h"

#include <cctype>
#include <filesystem>
#include <fstream>
#include <iterator>

namespace aar_geometry {
namespace {

std::string Lowercase(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string ReadWholeFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

}  // namespace

void CheckMeshStructure(const std::string& path) {
  const std::string ext = Lowercase(std::filesystem::path(path).extension().string());
  if (ext == ".stl")
    CheckStl(path, ReadWholeFile(path));
  else if (ext == ".ply")
    CheckPly(path, ReadWholeFile(path));
  else if (ext == ".dae")
    CheckCollada(path, ReadWholeFile(path));
}

}  // namespace aar_geometry
