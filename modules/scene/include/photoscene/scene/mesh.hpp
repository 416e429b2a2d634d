// The scene mesh: triangles with per-triangle material part ids and per-corner shading normals
// and texture coordinates.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "photoscene/core/math.hpp"
#include "photoscene/io/obj_io.hpp"

namespace ps {

/// A material part: the faces of the OBJ that share one `usemtl` name.
struct Part {
  std::string name;
  int id = -1;
  int triangleCount = 0;
  int generatedUvTriangles = 0;  ///< triangles whose UVs were generated (the OBJ had none)
};

/// Triangle mesh in world space (meters).
///
/// Corner arrays hold 3 entries per triangle: corner k of triangle t is at index 3 * t + k.
/// Shading normals are unit length; where the OBJ gave none they equal the geometric normal.
/// UVs follow the OBJ convention (v up); where the OBJ gave none they are generated (meters).
struct Mesh {
  std::vector<Vec3f> positions;
  std::vector<Eigen::Vector3i> triangles;  ///< indices into positions
  std::vector<Vec3f> cornerNormals;        ///< 3 per triangle
  std::vector<Vec2f> cornerUvs;            ///< 3 per triangle
  std::vector<int> partIds;                ///< per triangle, index into the scene's parts
  std::vector<uint8_t> generatedUv;        ///< per triangle: 1 where UVs were generated

  size_t numTriangles() const { return triangles.size(); }
  /// Unnormalized geometric normal (p1 - p0) x (p2 - p0); zero for a degenerate triangle.
  Vec3f faceNormalRaw(int t) const;
  /// Unit geometric normal, or zero for a degenerate triangle.
  Vec3f faceNormal(int t) const;
  float area(int t) const { return 0.5f * faceNormalRaw(t).norm(); }
  Eigen::AlignedBox3f bounds() const;
};

/// Builds a mesh from an OBJ: parts are its `usemtl` names (in order of first use).
/// Triangles without texture coordinates get UVs from generateUvs (reported in the parts).
Mesh meshFromObj(const io::ObjMesh& obj, std::vector<Part>* parts, const Vec3f& up);

/// Gives UVs (meters) to triangles with generatedUv[t] == 1 by a planar projection per face
/// cluster: connected triangles of one part whose normals share a dominant signed axis are
/// projected onto the plane of their mean normal, u horizontal and v up on walls, (u, v) along
/// the horizontal axes on floors and ceilings. Returns the number of triangles given UVs.
int generateUvs(Mesh& mesh, const Vec3f& up);

/// Two horizontal unit axes (e1, e2) with e1 x e2 = up, e1 the world axis least aligned with up.
void horizontalAxes(const Vec3f& up, Vec3f* e1, Vec3f* e2);

}  // namespace ps
