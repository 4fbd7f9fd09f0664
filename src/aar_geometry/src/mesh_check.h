// The checks LoadMesh (mesh_io.cpp) runs on a mesh file before assimp reads it, one file per
// format (stl_check.cpp, ply_check.cpp, collada_check.cpp); not installed. Each throws LoadError
// naming the file and saying what is wrong.
#pragma once

#include <string>

namespace aar_geometry {

// Debian's assimp 5.2 loops forever on a PLY cut off inside its header, exhausts memory on a
// COLLADA list with a non-numeric entry and leaks on a malformed ASCII STL. A PLY, COLLADA or
// STL file (by its extension, in any case) is read and checked here first, so that such files
// raise LoadError; other files are left to assimp.
void CheckMeshStructure(const std::string& path);

// An STL file's `text`: an ASCII STL (as assimp tells it from a binary one) against the
// standard's grammar (CheckAsciiStl, stl_check.cpp); a binary one is left to assimp.
void CheckStl(const std::string& path, const std::string& text);

// A PLY file's `text`: its header, and a body that holds what the header declares.
void CheckPly(const std::string& path, const std::string& text);

// A COLLADA file's `text`: its number lists and arrays, and the accessors into the arrays.
void CheckCollada(const std::string& path, const std::string& text);

}  // namespace aar_geometry
