#include "photoscene/scene/mesh.hpp"

#include "photoscene/core/log.hpp"

#include <Eigen/Geometry>

#include <map>
#include <numeric>

#include "photoscene/core/error.hpp"

namespace ps {

Vec3f Mesh::faceNormalRaw(int t) const {
  const Eigen::Vector3i& f = triangles[t];
  return (positions[f[1]] - positions[f[0]]).cross(positions[f[2]] - positions[f[0]]);
}

Vec3f Mesh::faceNormal(int t) const {
  const Vec3f n = faceNormalRaw(t);
  const float len = n.norm();
  return len > 1e-20f ? Vec3f(n / len) : Vec3f::Zero();
}

Eigen::AlignedBox3f Mesh::bounds() const {
  Eigen::AlignedBox3f box;
  for (const auto& f : triangles)
    for (int k = 0; k < 3; ++k) box.extend(positions[f[k]]);
  return box;
}

Mat3f ObjectPose::rotation(const Vec3f& up) const {
  return Eigen::AngleAxisf(yaw, up.normalized()).toRotationMatrix();
}

Vec3f objectPivot(const Mesh& mesh, int object, const Vec3f& up) {
  Vec3f e1, e2;
  horizontalAxes(up, &e1, &e2);
  Eigen::AlignedBox3f box;  // in (e1, e2, up) coordinates
  for (size_t t = 0; t < mesh.numTriangles(); ++t)
    if (mesh.objectIds[t] == object)
      for (int k = 0; k < 3; ++k) {
        const Vec3f& p = mesh.positions[mesh.triangles[t][k]];
        box.extend(Vec3f(p.dot(e1), p.dot(e2), p.dot(up)));
      }
  if (box.isEmpty()) return Vec3f::Zero();
  const Vec3f c = box.center();
  return e1 * c.x() + e2 * c.y() + up * box.min().z();
}

namespace {

// Makes the entries `index(t, k)` that the object's triangles use their own: an entry shared with
// a triangle outside the object is appended again and the object's corners re-pointed. Returns
// the entries the object now owns.
template <typename T, typename Index>
std::vector<int> detach(std::vector<T>& values, size_t triangles, const std::vector<int>& objectOf,
                        int object, Index index) {
  std::vector<int8_t> use(values.size(), 0);  // bit 1: the object's, bit 2: another's
  for (size_t t = 0; t < triangles; ++t)
    for (int k = 0; k < 3; ++k)
      if (const int i = index(t, k); i >= 0) use[i] |= objectOf[t] == object ? 1 : 2;
  std::vector<int> copy(values.size(), -1), owned;
  for (size_t t = 0; t < triangles; ++t) {
    if (objectOf[t] != object) continue;
    for (int k = 0; k < 3; ++k) {
      int& i = index(t, k);
      if (i < 0) continue;
      if (use[i] == 3) {
        if (copy[i] < 0) {
          copy[i] = static_cast<int>(values.size());
          values.push_back(values[i]);
          owned.push_back(copy[i]);
        }
        i = copy[i];
      } else if (use[i] == 1) {
        use[i] = 4;  // counted once
        owned.push_back(i);
      }
    }
  }
  return owned;
}

}  // namespace

void applyObjectPose(Mesh& mesh, int object, const ObjectPose& pose, const Vec3f& up) {
  if (pose.isIdentity()) return;
  const std::vector<int> owned =
      detach(mesh.positions, mesh.numTriangles(), mesh.objectIds, object,
             [&](size_t t, int k) -> int& { return mesh.triangles[t][k]; });
  for (int i : owned) mesh.positions[i] = pose.point(mesh.positions[i], up);
  const Mat3f r = pose.rotation(up);
  bool generated = false;
  for (size_t t = 0; t < mesh.numTriangles(); ++t) {
    if (mesh.objectIds[t] != object) continue;
    for (int k = 0; k < 3; ++k) mesh.cornerNormals[3 * t + k] = r * mesh.cornerNormals[3 * t + k];
    generated = generated || mesh.generatedUv[t];
  }
  if (generated) generateUvs(mesh, up);
}

void applyObjectPose(io::ObjMesh& mesh, int object, const ObjectPose& pose, const Vec3f& up) {
  if (pose.isIdentity()) return;
  const size_t n = mesh.triangles.size();
  const std::vector<int> positions =
      detach(mesh.positions, n, mesh.triangleObject, object,
             [&](size_t t, int k) -> int& { return mesh.triangles[t][k].position; });
  const std::vector<int> normals =
      detach(mesh.normals, n, mesh.triangleObject, object,
             [&](size_t t, int k) -> int& { return mesh.triangles[t][k].normal; });
  for (int i : positions) mesh.positions[i] = pose.point(mesh.positions[i], up);
  const Mat3f r = pose.rotation(up);
  for (int i : normals) mesh.normals[i] = r * mesh.normals[i];
}

void horizontalAxes(const Vec3f& up, Vec3f* e1, Vec3f* e2) {
  // the world axis least aligned with up, made orthogonal to it
  int axis = 0;
  for (int i = 1; i < 3; ++i)
    if (std::abs(up[i]) < std::abs(up[axis])) axis = i;
  Vec3f a = Vec3f::Zero();
  a[axis] = 1;
  *e1 = (a - up * up.dot(a)).normalized();
  *e2 = up.cross(*e1);  // e1 x e2 = e1 x (up x e1) = up
}

Mesh meshFromObj(const io::ObjMesh& obj, std::vector<Part>* parts, const Vec3f& up) {
  Mesh mesh;
  mesh.positions = obj.positions;
  const size_t n = obj.triangles.size();
  mesh.triangles.resize(n);
  mesh.cornerNormals.resize(3 * n);
  mesh.cornerUvs.resize(3 * n, Vec2f::Zero());
  mesh.partIds.resize(n);
  mesh.generatedUv.assign(n, 0);
  mesh.objectNames = obj.objectNames;
  mesh.objectIds = obj.triangleObject;
  mesh.objectIds.resize(n, -1);
  parts->clear();
  for (size_t i = 0; i < obj.materialNames.size(); ++i)
    parts->push_back(Part{obj.materialNames[i], static_cast<int>(i), 0, 0});
  for (size_t t = 0; t < n; ++t) {
    const auto& tri = obj.triangles[t];
    mesh.triangles[t] = Eigen::Vector3i(tri[0].position, tri[1].position, tri[2].position);
    mesh.partIds[t] = obj.triangleMaterial[t];
    (*parts)[obj.triangleMaterial[t]].triangleCount++;
  }
  for (size_t t = 0; t < n; ++t) {
    const auto& tri = obj.triangles[t];
    const Vec3f fn = mesh.faceNormal(static_cast<int>(t));
    bool hasUv = true;
    for (int k = 0; k < 3; ++k) {
      Vec3f nrm = tri[k].normal >= 0 ? obj.normals[tri[k].normal] : fn;
      if (nrm.squaredNorm() < 1e-12f) nrm = fn;
      mesh.cornerNormals[3 * t + k] = nrm;
      if (tri[k].texcoord >= 0) mesh.cornerUvs[3 * t + k] = obj.texcoords[tri[k].texcoord];
      else hasUv = false;
    }
    if (!hasUv) mesh.generatedUv[t] = 1;
  }
  const int generated = generateUvs(mesh, up);
  if (generated > 0) {
    for (size_t t = 0; t < n; ++t)
      if (mesh.generatedUv[t]) (*parts)[mesh.partIds[t]].generatedUvTriangles++;
    spdlog::info("generated UVs (planar per face cluster, meters) for {} of {} triangles", generated, n);
  }
  return mesh;
}

namespace {
int findRoot(std::vector<int>& parent, int i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

int dominantAxisKey(const Vec3f& n) {
  int axis = 0;
  for (int i = 1; i < 3; ++i)
    if (std::abs(n[i]) > std::abs(n[axis])) axis = i;
  return 2 * axis + (n[axis] < 0 ? 1 : 0);
}
}  // namespace

int generateUvs(Mesh& mesh, const Vec3f& up) {
  const int n = static_cast<int>(mesh.numTriangles());
  std::vector<int> todo;
  for (int t = 0; t < n; ++t)
    if (mesh.generatedUv[t]) todo.push_back(t);
  if (todo.empty()) return 0;

  // Union triangles of the same part and dominant axis that share a vertex.
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  std::vector<int> key(n, -1);
  for (int t : todo) key[t] = mesh.partIds[t] * 8 + dominantAxisKey(mesh.faceNormal(t));
  std::map<std::pair<int, int>, int> firstAtVertex;  // (vertex, key) -> triangle
  for (int t : todo) {
    for (int k = 0; k < 3; ++k) {
      auto [it, inserted] = firstAtVertex.emplace(std::make_pair(mesh.triangles[t][k], key[t]), t);
      if (!inserted) {
        const int a = findRoot(parent, it->second), b = findRoot(parent, t);
        if (a != b) parent[b] = a;
      }
    }
  }
  std::map<int, Vec3f> clusterNormal;
  for (int t : todo) {
    auto& acc = clusterNormal.try_emplace(findRoot(parent, t), Vec3f::Zero()).first->second;
    acc += mesh.faceNormalRaw(t);  // area weighted
  }
  Vec3f e1, e2;
  horizontalAxes(up, &e1, &e2);
  std::map<int, std::pair<Vec3f, Vec3f>> frames;
  for (auto& [root, acc] : clusterNormal) {
    Vec3f m = acc.norm() > 1e-20f ? Vec3f(acc.normalized()) : up;
    Vec3f tu, tv;
    if (std::abs(m.dot(up)) > 0.7f) {
      // floor or ceiling: u along e1, v completes a right-handed frame with the normal
      tu = e1;
      tv = m.cross(tu).normalized();
    } else {
      // wall: u horizontal (to the right seen from the front), v up
      tu = up.cross(m).normalized();
      tv = m.cross(tu).normalized();
    }
    frames[root] = {tu, tv};
  }
  for (int t : todo) {
    const auto& [tu, tv] = frames[findRoot(parent, t)];
    for (int k = 0; k < 3; ++k) {
      const Vec3f& p = mesh.positions[mesh.triangles[t][k]];
      mesh.cornerUvs[3 * t + k] = Vec2f(p.dot(tu), p.dot(tv));
    }
  }
  return static_cast<int>(todo.size());
}

}  // namespace ps
