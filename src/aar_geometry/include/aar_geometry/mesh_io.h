#pragma once

#include <string>

#include "aar_geometry/triangle_mesh.h"

namespace aar_geometry {

// Loads a triangle mesh through assimp (OBJ, STL, DAE, PLY and the other formats assimp reads).
// The node hierarchy's transforms are applied; each assimp mesh becomes a part named after its
// node (or mesh) so that labelled models keep their labels. Vertices are not welded: call
// WeldVertices when adjacency matters. Units are the file's: COLLADA's <unit> is honoured.
// Throws LoadError naming the file for a missing, empty, unreadable or malformed file, or one
// that holds no triangles.
TriangleMesh LoadMesh(const std::string& path);

// Writes a Wavefront OBJ with one object ("o <part>") per part, vertices with 6 decimals [m],
// which LoadMesh reads back with the same parts. Throws LoadError if the file cannot be written.
void WriteObj(const std::string& path, const TriangleMesh& mesh, const std::string& comment = "");

}  // namespace aar_geometry
