// Wavefront OBJ through tinyobjloader: positions, normals, texture coordinates and `usemtl`
// material parts. Polygons with more than three corners are triangulated (ear clipping in the
// polygon's plane). Faces without `usemtl` belong to the part "default". `mtllib` is ignored:
// a part is its `usemtl` name, whatever the .mtl says.
#pragma once

#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "photoscene/core/math.hpp"

namespace ps::io {

namespace fs = std::filesystem;

/// One triangle corner: 0-based indices into ObjMesh's arrays, -1 where the face gave none.
struct ObjCorner {
  int position = -1;
  int texcoord = -1;
  int normal = -1;
};

struct ObjMesh {
  std::vector<Vec3f> positions;                   ///< meters (as stored)
  std::vector<Vec2f> texcoords;                   ///< (u, v), v up (OBJ convention)
  std::vector<Vec3f> normals;                     ///< as stored (normalized on read)
  std::vector<std::array<ObjCorner, 3>> triangles;
  std::vector<int> triangleMaterial;              ///< index into materialNames, per triangle
  std::vector<int> triangleLine;                  ///< 1-based line of the source face
  std::vector<std::string> materialNames;         ///< `usemtl` names, in order of first use
  int polygonsTriangulated = 0;                   ///< faces with more than 3 corners
};

/// Reads an OBJ. Throws ps::InputError naming the file and line for: a missing file, a face
/// index out of range or 0, a face with fewer than 3 corners, non-finite coordinates, a file
/// with no faces.
ObjMesh readObj(const fs::path& path);

/// Writes an OBJ (one `usemtl` group per material in triangle order), atomically.
void writeObj(const fs::path& path, const ObjMesh& mesh);

}  // namespace ps::io
