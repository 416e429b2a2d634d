#include "photoscene/io/obj_io.hpp"

#include <tiny_obj_loader.h>

#include <cctype>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "photoscene/core/error.hpp"
#include "photoscene/io/files.hpp"

namespace ps::io {

namespace {

struct RawCorner {
  int v, vt, vn;  // resolved 0-based (positive raw indices are checked at the end)
};

struct ParseState {
  ObjMesh mesh;
  std::map<std::string, int> materialIndex;
  int currentMaterial = -1;
  int currentO = -1, currentG = -1;  // the latest `o` and `g` names (indices into the lists below)
  std::vector<std::string> oNames, gNames;
  std::vector<int> triangleO, triangleG;
  int line = 0;
  std::string file;
  std::vector<RawCorner> corners;
  std::vector<std::string> pendingErrors;
  ObjLimits limits;
};

std::string withThousands(int64_t n) {
  std::string s = std::to_string(n);
  for (int i = static_cast<int>(s.size()) - 3; i > 0; i -= 3) s.insert(static_cast<size_t>(i), ",");
  return s;
}

int materialFor(ParseState& s) {
  if (s.currentMaterial >= 0) return s.currentMaterial;
  auto it = s.materialIndex.find("default");
  if (it != s.materialIndex.end()) return it->second;
  const int id = static_cast<int>(s.mesh.materialNames.size());
  s.mesh.materialNames.push_back("default");
  s.materialIndex["default"] = id;
  return id;
}

/// OBJ raw index (1-based, negative = relative to the count so far, 0 = none) to 0-based.
/// Returns -1 for "none", throws on 0 where an index is required.
int resolve(int raw, int countSoFar) {
  if (raw > 0) return raw - 1;
  if (raw < 0) return countSoFar + raw;  // may be < 0: caught by the range check
  return -1;
}

/// Ear-clipping triangulation of a planar polygon given by its corner positions.
std::vector<std::array<int, 3>> triangulate(const std::vector<Vec3f>& p) {
  const int n = static_cast<int>(p.size());
  std::vector<std::array<int, 3>> tris;
  // Newell normal of the polygon.
  Vec3f normal = Vec3f::Zero();
  for (int i = 0; i < n; ++i) {
    const Vec3f& a = p[i];
    const Vec3f& b = p[(i + 1) % n];
    normal += Vec3f((a.y() - b.y()) * (a.z() + b.z()), (a.z() - b.z()) * (a.x() + b.x()),
                    (a.x() - b.x()) * (a.y() + b.y()));
  }
  if (normal.norm() < 1e-20f) {  // degenerate polygon: fan
    for (int i = 1; i + 1 < n; ++i) tris.push_back({0, i, i + 1});
    return tris;
  }
  normal.normalize();
  std::vector<int> idx(n);
  for (int i = 0; i < n; ++i) idx[i] = i;
  auto cross = [&](int a, int b, int c) { return (p[b] - p[a]).cross(p[c] - p[a]).dot(normal); };
  auto inside = [&](int a, int b, int c, int q) {
    return cross(a, b, q) >= 0 && cross(b, c, q) >= 0 && cross(c, a, q) >= 0;
  };
  int guard = 0;
  while (idx.size() > 3 && guard++ < n * n) {
    bool clipped = false;
    const int m = static_cast<int>(idx.size());
    for (int i = 0; i < m; ++i) {
      const int a = idx[(i + m - 1) % m], b = idx[i], c = idx[(i + 1) % m];
      if (cross(a, b, c) <= 0) continue;  // reflex or degenerate corner
      bool ear = true;
      for (int j = 0; j < m && ear; ++j) {
        const int q = idx[j];
        if (q == a || q == b || q == c) continue;
        if (inside(a, b, c, q)) ear = false;
      }
      if (!ear) continue;
      tris.push_back({a, b, c});
      idx.erase(idx.begin() + i);
      clipped = true;
      break;
    }
    if (!clipped) break;
  }
  if (idx.size() == 3) {
    tris.push_back({idx[0], idx[1], idx[2]});
  } else if (idx.size() > 3) {  // self-intersecting: fan over what is left
    for (size_t i = 1; i + 1 < idx.size(); ++i) tris.push_back({idx[0], idx[i], idx[i + 1]});
  }
  return tris;
}

void onVertex(void* user, float x, float y, float z, float) {
  auto& s = *static_cast<ParseState*>(user);
  if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
    throw InputError(s.file, "line " + std::to_string(s.line), "vertex with a non-finite coordinate");
  if (static_cast<int64_t>(s.mesh.positions.size()) >= s.limits.maxVertices)
    throw InputError(s.file, "line " + std::to_string(s.line),
                     "expected at most " + withThousands(s.limits.maxVertices) +
                         " vertices (the supported OBJ size); refused at the first vertex over it");
  s.mesh.positions.emplace_back(x, y, z);
}

void onNormal(void* user, float x, float y, float z) {
  auto& s = *static_cast<ParseState*>(user);
  Vec3f n(x, y, z);
  const float len = n.norm();
  if (!std::isfinite(len)) throw InputError(s.file, "line " + std::to_string(s.line), "normal with a non-finite coordinate");
  s.mesh.normals.push_back(len > 0 ? Vec3f(n / len) : Vec3f::Zero());
}

void onTexcoord(void* user, float u, float v, float) {
  auto& s = *static_cast<ParseState*>(user);
  if (!std::isfinite(u) || !std::isfinite(v))
    throw InputError(s.file, "line " + std::to_string(s.line), "texture coordinate that is not finite");
  s.mesh.texcoords.emplace_back(u, v);
}

void onUsemtl(void* user, const char* name, int) {
  auto& s = *static_cast<ParseState*>(user);
  std::string n = name;
  while (!n.empty() && std::isspace(static_cast<unsigned char>(n.back()))) n.pop_back();
  if (n.empty()) n = "default";
  auto it = s.materialIndex.find(n);
  if (it == s.materialIndex.end()) {
    const int id = static_cast<int>(s.mesh.materialNames.size());
    s.mesh.materialNames.push_back(n);
    it = s.materialIndex.emplace(n, id).first;
  }
  s.currentMaterial = it->second;
}

void onFace(void* user, tinyobj::index_t* indices, int count) {
  auto& s = *static_cast<ParseState*>(user);
  const std::string where = "line " + std::to_string(s.line);
  if (count < 3)
    throw InputError(s.file, where, "a face needs at least 3 corners, got " + std::to_string(count));
  std::vector<ObjCorner> corners(count);
  const int nv = static_cast<int>(s.mesh.positions.size());
  const int nt = static_cast<int>(s.mesh.texcoords.size());
  const int nn = static_cast<int>(s.mesh.normals.size());
  for (int i = 0; i < count; ++i) {
    if (indices[i].vertex_index == 0)
      throw InputError(s.file, where, "face vertex index 0 (OBJ indices start at 1)");
    corners[i].position = resolve(indices[i].vertex_index, nv);
    corners[i].texcoord = resolve(indices[i].texcoord_index, nt);
    corners[i].normal = resolve(indices[i].normal_index, nn);
    if (corners[i].position < 0)
      throw InputError(s.file, where, "relative face index " + std::to_string(indices[i].vertex_index) +
                                          " points before the first vertex");
  }
  const int material = materialFor(s);
  auto push = [&](const ObjCorner& a, const ObjCorner& b, const ObjCorner& c) {
    if (static_cast<int64_t>(s.mesh.triangles.size()) >= s.limits.maxTriangles)
      throw InputError(
          s.file, where,
          "expected at most " + withThousands(s.limits.maxTriangles) +
              " triangles (the supported OBJ size); refused at the first face over it");
    s.mesh.triangles.push_back({a, b, c});
    s.mesh.triangleMaterial.push_back(material);
    s.mesh.triangleLine.push_back(s.line);
    s.triangleO.push_back(s.currentO);
    s.triangleG.push_back(s.currentG);
  };
  if (count == 3) {
    push(corners[0], corners[1], corners[2]);
    return;
  }
  ++s.mesh.polygonsTriangulated;
  std::vector<Vec3f> pos(count);
  for (int i = 0; i < count; ++i) {
    const int v = corners[i].position;
    if (v >= nv)  // forward reference: triangulate as a fan; range is checked at the end
      pos.assign(count, Vec3f::Zero());
    else
      pos[i] = s.mesh.positions[v];
  }
  for (const auto& t : triangulate(pos)) push(corners[t[0]], corners[t[1]], corners[t[2]]);
}

// `o NAME` / `g NAME ...`: the object the following faces belong to (one name per line, as written;
// a `g` line with several names or none is one group under its whole text).
void onObjectLine(ParseState& s, const std::string& line, size_t first) {
  const bool isO = line[first] == 'o';
  std::string name = line.substr(first + 1);
  const size_t a = name.find_first_not_of(" \t");
  name = a == std::string::npos ? std::string() : name.substr(a);
  while (!name.empty() && std::isspace(static_cast<unsigned char>(name.back()))) name.pop_back();
  if (name.empty()) name = isO ? "object" : "default";
  std::vector<std::string>& names = isO ? s.oNames : s.gNames;
  names.push_back(name);
  (isO ? s.currentO : s.currentG) = static_cast<int>(names.size()) - 1;
}

}  // namespace

ObjMesh readObj(const fs::path& path, const ObjLimits& limits) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw InputError(path.string(), "", "OBJ file not found");
  if (const auto bytes = fs::file_size(path, ec);
      !ec && static_cast<int64_t>(bytes) > limits.maxFileBytes)
    throw InputError(path.string(), "",
                     "expected an OBJ of at most " + withThousands(limits.maxFileBytes >> 20) +
                         " MiB, " + withThousands(limits.maxTriangles) + " triangles and " +
                         withThousands(limits.maxVertices) +
                         " vertices (the supported size), but the file is " +
                         withThousands(static_cast<int64_t>(bytes)) + " bytes (not read)");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), "", "cannot open the OBJ file");

  ParseState state;
  state.file = path.string();
  state.limits = limits;
  tinyobj::callback_t cb;
  cb.vertex_cb = onVertex;
  cb.normal_cb = onNormal;
  cb.texcoord_cb = onTexcoord;
  cb.index_cb = onFace;
  cb.usemtl_cb = onUsemtl;

  // tinyobjloader's callback API parses and we get every element in file order; feeding it line by
  // line lets every error name its line.
  std::string line;
  while (std::getline(in, line)) {
    ++state.line;
    if (line.empty()) continue;
    const size_t first = line.find_first_not_of(" \t");
    if (first == std::string::npos) continue;
    const char c = line[first];
    if ((c == 'o' || c == 'g') && first + 1 < line.size() &&
        (line[first + 1] == ' ' || line[first + 1] == '\t')) {
      onObjectLine(state, line, first);
      continue;
    }
    if (c != 'v' && c != 'f' && c != 'u') continue;  // comments, mtllib, s, l, p
    std::istringstream ls(line);
    std::string warn, err;
    tinyobj::LoadObjWithCallback(ls, cb, &state, nullptr, &warn, &err);
  }

  ObjMesh& mesh = state.mesh;
  const bool byO = !state.oNames.empty();
  mesh.objectNames = byO ? state.oNames : state.gNames;
  mesh.triangleObject = byO ? state.triangleO : state.triangleG;
  if (mesh.triangles.empty())
    throw InputError(path.string(), "", "no faces: expected at least one triangle (lines starting with 'f')");
  const int nv = static_cast<int>(mesh.positions.size());
  const int nt = static_cast<int>(mesh.texcoords.size());
  const int nn = static_cast<int>(mesh.normals.size());
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (const ObjCorner& c : mesh.triangles[t]) {
      const std::string where = "line " + std::to_string(mesh.triangleLine[t]);
      if (c.position >= nv)
        throw InputError(path.string(), where, "face refers to vertex " + std::to_string(c.position + 1) +
                                                   ", but the file has " + std::to_string(nv) + " vertices");
      if (c.texcoord >= nt)
        throw InputError(path.string(), where, "face refers to texture coordinate " + std::to_string(c.texcoord + 1) +
                                                   ", but the file has " + std::to_string(nt));
      if (c.normal >= nn)
        throw InputError(path.string(), where, "face refers to normal " + std::to_string(c.normal + 1) +
                                                   ", but the file has " + std::to_string(nn));
    }
  }
  return mesh;
}

void writeObj(const fs::path& path, const ObjMesh& mesh) {
  std::ostringstream os;
  os.precision(9);
  os << "# written by photoscene\n";
  for (const Vec3f& p : mesh.positions) os << "v " << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  for (const Vec2f& t : mesh.texcoords) os << "vt " << t.x() << ' ' << t.y() << '\n';
  for (const Vec3f& n : mesh.normals) os << "vn " << n.x() << ' ' << n.y() << ' ' << n.z() << '\n';
  int current = -2, object = -1;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const int o = t < mesh.triangleObject.size() ? mesh.triangleObject[t] : -1;
    if (o != object && o >= 0 && o < static_cast<int>(mesh.objectNames.size())) {
      os << "o " << mesh.objectNames[o] << '\n';
      object = o;
      current = -2;  // a new object restates its material
    }
    const int m = t < mesh.triangleMaterial.size() ? mesh.triangleMaterial[t] : -1;
    if (m != current && m >= 0 && m < static_cast<int>(mesh.materialNames.size())) {
      os << "usemtl " << mesh.materialNames[m] << '\n';
      current = m;
    }
    os << 'f';
    for (const ObjCorner& c : mesh.triangles[t]) {
      os << ' ' << c.position + 1;
      if (c.texcoord >= 0 || c.normal >= 0) os << '/';
      if (c.texcoord >= 0) os << c.texcoord + 1;
      if (c.normal >= 0) os << '/' << c.normal + 1;
    }
    os << '\n';
  }
  writeTextFile(path, os.str());
}

}  // namespace ps::io
