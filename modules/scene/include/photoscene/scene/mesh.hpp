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
  std::vector<int> objectIds;              ///< per triangle, index into objectNames (-1: none)
  std::vector<std::string> objectNames;    ///< the OBJ's objects (io::ObjMesh::objectNames)

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

/// A move of one rigid object about the scene's up axis, as furniture is misplaced in a coarse
/// CAD model: p' = pivot + shift + scale R(yaw) (p - pivot), R the rotation by `yaw` radians about
/// `up` (right-handed), `pivot` the object's bottom centre. Normals turn by R alone.
struct ObjectPose {
  Vec3f pivot = Vec3f::Zero();
  Vec3f shift = Vec3f::Zero();  ///< meters, orthogonal to up
  float yaw = 0;                ///< radians
  float scale = 1;
  bool isIdentity() const { return shift.isZero(0) && yaw == 0 && scale == 1; }
  Mat3f rotation(const Vec3f& up) const;
  Vec3f point(const Vec3f& p, const Vec3f& up) const {
    return pivot + shift + scale * (rotation(up) * (p - pivot));
  }
};

/// The bottom centre of an object's bounds in the frame of `up` (horizontalAxes): the pivot of
/// its ObjectPose.
Vec3f objectPivot(const Mesh& mesh, int object, const Vec3f& up);

/// Moves the triangles of `object` by `pose`: positions they share with other triangles are
/// duplicated first, corner normals turn, generated UVs are generated again. The same move as
/// the io::ObjMesh overload, so that a twin written with it reads back as this mesh.
void applyObjectPose(Mesh& mesh, int object, const ObjectPose& pose, const Vec3f& up);
void applyObjectPose(io::ObjMesh& mesh, int object, const ObjectPose& pose, const Vec3f& up);

/// Two horizontal unit axes (e1, e2) with e1 x e2 = up, e1 the world axis least aligned with up.
void horizontalAxes(const Vec3f& up, Vec3f* e1, Vec3f* e2);

}  // namespace ps
