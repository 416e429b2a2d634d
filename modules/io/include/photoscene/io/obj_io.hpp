// Wavefront OBJ through tinyobjloader: positions, normals, texture coordinates and `usemtl`
// material parts. Polygons with more than three corners are triangulated (ear clipping in the
// polygon's plane). Faces without `usemtl` belong to the part "default". `mtllib` is ignored:
// a part is its `usemtl` name, whatever the .mtl says. Objects are the `o` names (the `g` names
// in a file without `o` lines): the rigid pieces whose pose may be refined (align/pose.hpp).
#pragma once

#include <array>
#include <cstdint>
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
  std::vector<int> triangleObject;                ///< index into objectNames, -1: before any
  std::vector<std::string> objectNames;           ///< `o` (else `g`) names, in file order
  int polygonsTriangulated = 0;                   ///< faces with more than 3 corners
};

/// What readObj accepts (issue 9, resource limits). A run holds about 0.5 KiB per triangle
/// (measured: 1,002,534 triangles, peak 536 MiB for a whole `photoscene run`), so the defaults
/// keep a run of the largest accepted OBJ near 2.5 GiB.
struct ObjLimits {
  int64_t maxFileBytes = int64_t(1) << 30;  ///< 1 GiB, checked before the file is read
  int64_t maxTriangles = 5'000'000;         ///< after triangulating polygons
  int64_t maxVertices = 5'000'000;          ///< `v` lines
};

/// Reads an OBJ. Throws ps::InputError naming the file and line for: a missing file, a face
/// index out of range or 0, a face with fewer than 3 corners, non-finite coordinates, a file
/// with no faces, a file over `limits` (refused as soon as a limit is passed, before the rest
/// is read).
ObjMesh readObj(const fs::path& path, const ObjLimits& limits = {});

/// Writes an OBJ (one `usemtl` group per material in triangle order, an `o` line where the object
/// changes), atomically.
void writeObj(const fs::path& path, const ObjMesh& mesh);

}  // namespace ps::io
