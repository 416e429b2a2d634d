// Building the OBJ of a synthetic scene, for the programs that make one
// (samples/tools/make_sample_scene.cpp, bench/bench_real_textures.cpp): parts, quads, and the UVs
// the scene gives the geometry written into the file itself.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "photoscene/io.hpp"
#include "photoscene/scene.hpp"

namespace ps::tools {

/// The index of part `name` in obj.materialNames (its `usemtl` name), appended when absent.
inline int materialIndex(io::ObjMesh& obj, const std::string& name) {
  for (size_t i = 0; i < obj.materialNames.size(); ++i)
    if (obj.materialNames[i] == name) return static_cast<int>(i);
  obj.materialNames.push_back(name);
  return static_cast<int>(obj.materialNames.size()) - 1;
}

/// Appends the quad `corners` (in order round it, counter-clockwise seen from its front) as the
/// triangles 0 1 2 and 0 2 3 of part `material` (source line 0: no file).
inline void addQuad(io::ObjMesh& obj, const std::array<Vec3f, 4>& corners, int material) {
  const int base = static_cast<int>(obj.positions.size());
  for (const Vec3f& p : corners) obj.positions.push_back(p);
  auto corner = [&](int k) { return io::ObjCorner{base + k, -1, -1}; };
  obj.triangles.push_back({corner(0), corner(1), corner(2)});
  obj.triangles.push_back({corner(0), corner(2), corner(3)});
  for (int k = 0; k < 2; ++k) {
    obj.triangleMaterial.push_back(material);
    obj.triangleLine.push_back(0);
  }
}

/// Replaces the texture coordinates of `obj` by the UVs meshFromObj gives its triangles (+y up;
/// a triangle without any gets generateUvs': metres, planar per face cluster), one per corner.
/// Returns meshFromObj's parts.
inline std::vector<Part> writeUvsIntoObj(io::ObjMesh& obj) {
  std::vector<Part> parts;
  const Mesh mesh = meshFromObj(obj, &parts, Vec3f(0, 1, 0));
  obj.texcoords.clear();
  for (size_t t = 0; t < obj.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      obj.texcoords.push_back(mesh.cornerUvs[3 * t + k]);
      obj.triangles[t][k].texcoord = static_cast<int>(obj.texcoords.size()) - 1;
    }
  return parts;
}

}  // namespace ps::tools
