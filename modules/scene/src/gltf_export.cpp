#include "photoscene/scene/gltf_export.hpp"

#include "photoscene/core/log.hpp"
#include <tiny_gltf.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <unordered_map>

#include "photoscene/core/error.hpp"
#include "photoscene/core/timer.hpp"
#include "photoscene/io/files.hpp"
#include "photoscene/io/image_io.hpp"
#include "photoscene/io/json.hpp"
#include "photoscene/io/scene_json.hpp"
#include "photoscene/io/uri.hpp"

namespace ps {

namespace fs = std::filesystem;

namespace {

constexpr int kFloat = TINYGLTF_COMPONENT_TYPE_FLOAT;
constexpr int kUint32 = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;

/// `path` relative to `base` with '/' separators (a glTF URI, RFC 3986); absolute when not
/// under a common root.
std::string uriFor(const fs::path& path, const fs::path& base) {
  return io::relativeUri(path, base);
}

/// Appends raw bytes to the buffer (4-byte aligned) and adds a buffer view; returns its index.
int addBufferView(tinygltf::Model& model, const void* data, size_t bytes, int target) {
  auto& buf = model.buffers[0].data;
  while (buf.size() % 4) buf.push_back(0);
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = buf.size();
  view.byteLength = bytes;
  view.target = target;
  const auto* p = static_cast<const unsigned char*>(data);
  buf.insert(buf.end(), p, p + bytes);
  model.bufferViews.push_back(view);
  return static_cast<int>(model.bufferViews.size()) - 1;
}

int addFloatAccessor(tinygltf::Model& model, const std::vector<float>& values, int components,
                     bool minMax) {
  const size_t count = values.size() / components;
  tinygltf::Accessor acc;
  acc.bufferView = addBufferView(model, values.data(), values.size() * sizeof(float),
                                 TINYGLTF_TARGET_ARRAY_BUFFER);
  acc.componentType = kFloat;
  acc.count = count;
  acc.type = components == 2 ? TINYGLTF_TYPE_VEC2
                             : (components == 3 ? TINYGLTF_TYPE_VEC3 : TINYGLTF_TYPE_VEC4);
  if (minMax && count > 0) {
    acc.minValues.assign(components, 1e300);
    acc.maxValues.assign(components, -1e300);
    for (size_t i = 0; i < count; ++i)
      for (int c = 0; c < components; ++c) {
        const double v = values[i * components + c];
        acc.minValues[c] = std::min(acc.minValues[c], v);
        acc.maxValues[c] = std::max(acc.maxValues[c], v);
      }
  }
  model.accessors.push_back(acc);
  return static_cast<int>(model.accessors.size()) - 1;
}

int addIndexAccessor(tinygltf::Model& model, const std::vector<uint32_t>& indices) {
  tinygltf::Accessor acc;
  acc.bufferView = addBufferView(model, indices.data(), indices.size() * sizeof(uint32_t),
                                 TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
  acc.componentType = kUint32;
  acc.count = indices.size();
  acc.type = TINYGLTF_TYPE_SCALAR;
  model.accessors.push_back(acc);
  return static_cast<int>(model.accessors.size()) - 1;
}

/// Vertex arrays of one primitive.
struct PrimitiveData {
  std::vector<float> positions, normals, tangents, uvs;
  std::vector<uint32_t> indices;
  size_t vertexCount() const { return positions.size() / 3; }
};

int addMesh(tinygltf::Model& model, const std::string& name, const PrimitiveData& d, int material) {
  tinygltf::Primitive prim;
  prim.mode = TINYGLTF_MODE_TRIANGLES;
  prim.material = material;
  prim.attributes["POSITION"] = addFloatAccessor(model, d.positions, 3, true);
  prim.attributes["NORMAL"] = addFloatAccessor(model, d.normals, 3, false);
  if (!d.tangents.empty())
    prim.attributes["TANGENT"] = addFloatAccessor(model, d.tangents, 4, false);
  if (!d.uvs.empty()) prim.attributes["TEXCOORD_0"] = addFloatAccessor(model, d.uvs, 2, false);
  prim.indices = addIndexAccessor(model, d.indices);
  tinygltf::Mesh mesh;
  mesh.name = name;
  mesh.primitives.push_back(prim);
  model.meshes.push_back(mesh);
  tinygltf::Node node;
  node.name = name;
  node.mesh = static_cast<int>(model.meshes.size()) - 1;
  model.nodes.push_back(node);
  return static_cast<int>(model.nodes.size()) - 1;
}

/// The primitive of one part: corners deduplicated on (position index, normal, uv); UVs are the
/// transformed t with v flipped; tangents follow dP/dt_u.
PrimitiveData partPrimitive(const Mesh& mesh, int partId, const UvTransform& uvt, bool tangents) {
  PrimitiveData d;
  struct Key {
    int p;
    float n[3], uv[2];
    bool operator==(const Key& o) const { return std::memcmp(this, &o, sizeof(Key)) == 0; }
  };
  struct KeyHash {
    size_t operator()(const Key& k) const {
      size_t h = std::hash<int>()(k.p);
      const auto* w = reinterpret_cast<const uint32_t*>(k.n);
      for (int i = 0; i < 5; ++i) h = h * 1000003u ^ w[i];
      return h;
    }
  };
  std::unordered_map<Key, uint32_t, KeyHash> index;
  std::vector<Vec3f> tangentSum;
  std::vector<float> bitangentSign;
  for (size_t t = 0; t < mesh.numTriangles(); ++t) {
    if (mesh.partIds[t] != partId) continue;
    const Eigen::Vector3i& tri = mesh.triangles[t];
    // per-triangle tangent frame of t (dP/dt_u, dP/dt_v)
    Vec3f T = Vec3f::UnitX(), B = Vec3f::UnitY();
    if (tangents) {
      const Vec3f p0 = mesh.positions[tri[0]], p1 = mesh.positions[tri[1]],
                  p2 = mesh.positions[tri[2]];
      const Vec2f u0 = mesh.cornerUvs[3 * t], u1 = mesh.cornerUvs[3 * t + 1],
                  u2 = mesh.cornerUvs[3 * t + 2];
      const Vec3f e1 = p1 - p0, e2 = p2 - p0;
      const Vec2f d1 = u1 - u0, d2 = u2 - u0;
      const float det = d1.x() * d2.y() - d2.x() * d1.y();
      Vec3f dPdu = Vec3f::Zero(), dPdv = Vec3f::Zero();
      if (std::abs(det) > 1e-20f) {
        dPdu = (e1 * d2.y() - e2 * d1.y()) / det;
        dPdv = (e2 * d1.x() - e1 * d2.x()) / det;
      }
      Vec3f n = mesh.faceNormal(static_cast<int>(t));
      if (n.isZero()) n = mesh.cornerNormals[3 * t];
      tangentFrame(dPdu, dPdv, n, uvt, &T, &B);
    }
    for (int k = 0; k < 3; ++k) {
      const Vec3f n = mesh.cornerNormals[3 * t + k];
      const Vec2f tc = uvt.apply(mesh.cornerUvs[3 * t + k]);
      Key key{tri[k], {n.x(), n.y(), n.z()}, {tc.x(), 1.0f - tc.y()}};
      auto [it, inserted] = index.emplace(key, static_cast<uint32_t>(d.vertexCount()));
      if (inserted) {
        const Vec3f& p = mesh.positions[tri[k]];
        d.positions.insert(d.positions.end(), {p.x(), p.y(), p.z()});
        d.normals.insert(d.normals.end(), {n.x(), n.y(), n.z()});
        d.uvs.insert(d.uvs.end(), {key.uv[0], key.uv[1]});
        tangentSum.push_back(Vec3f::Zero());
        bitangentSign.push_back(0.0f);
      }
      if (tangents) {
        tangentSum[it->second] += T;
        bitangentSign[it->second] += n.cross(T).dot(B) >= 0 ? 1.0f : -1.0f;
      }
      d.indices.push_back(it->second);
    }
  }
  if (tangents) {
    for (size_t v = 0; v < d.vertexCount(); ++v) {
      const Vec3f n(d.normals[3 * v], d.normals[3 * v + 1], d.normals[3 * v + 2]);
      Vec3f t = tangentSum[v] - n * n.dot(tangentSum[v]);
      if (!(t.norm() > 1e-8f)) {
        Vec3f b;
        orthonormalBasis(n, t, b);
      }
      t.normalize();
      d.tangents.insert(d.tangents.end(),
                        {t.x(), t.y(), t.z(), bitangentSign[v] >= 0 ? 1.0f : -1.0f});
    }
  }
  return d;
}

/// Sets emissiveFactor (+ KHR_materials_emissive_strength where a channel exceeds 1).
void setEmission(tinygltf::Material& mat, const Vec3f& radiance,
                 std::set<std::string>& extensions) {
  const float m = std::max(radiance.maxCoeff(), 0.0f);
  if (m <= 0) return;
  const float scale = m > 1.0f ? m : 1.0f;
  mat.emissiveFactor = {radiance.x() / scale, radiance.y() / scale, radiance.z() / scale};
  if (scale > 1.0f) {
    tinygltf::Value::Object ext;
    ext["emissiveStrength"] = tinygltf::Value(static_cast<double>(scale));
    mat.extensions["KHR_materials_emissive_strength"] = tinygltf::Value(ext);
    extensions.insert("KHR_materials_emissive_strength");
  }
}

/// Writes a CV_32FC3 image of `size` from a per-texel function (row 0 on top).
template <typename F>
cv::Mat makeImage(int width, int height, F&& f) {
  cv::Mat img(height, width, CV_32FC3);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const Vec3f v = f(x, y);
      img.at<cv::Vec3f>(y, x) = cv::Vec3f(v.x(), v.y(), v.z());
    }
  return img;
}

class GltfBuilder {
 public:
  GltfBuilder(const Twin& twin, const fs::path& outDir, const GltfExportOptions& options)
      : twin_(twin), outDir_(outDir), options_(options) {
    model_.asset.version = "2.0";
    model_.asset.generator = "photoscene";
    model_.buffers.emplace_back();
    tinygltf::Sampler sampler;
    sampler.magFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
    sampler.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR;
    sampler.wrapS = TINYGLTF_TEXTURE_WRAP_REPEAT;
    sampler.wrapT = TINYGLTF_TEXTURE_WRAP_REPEAT;
    model_.samplers.push_back(sampler);
  }

  GltfExportSummary build() {
    const Scene& scene = twin_.scene;
    std::set<int> windows;
    for (int p : scene.lights.openingParts()) windows.insert(p);
    std::map<int, Vec3f> partEmission;
    for (const Light* l : scene.lights.all())
      for (int p : l->emittingParts())
        if (p >= 0) partEmission[p] = l->scale().value_or(Vec3f::Ones());

    std::vector<int> children;
    for (const Part& part : scene.parts) {
      const bool window = windows.count(part.id) > 0;
      if (window && !options_.includeWindowParts) continue;
      if (part.triangleCount == 0) continue;
      const PartMaterial& pm = twin_.materials.at(part.id);
      int mat = addPartMaterial(part, pm, window);
      if (auto it = partEmission.find(part.id); it != partEmission.end()) {
        setEmission(model_.materials[mat], it->second, extensions_);
        ++summary_.emitters;
      }
      // tangents only serve a normal texture
      const bool tangents =
          options_.exportTangents && model_.materials[mat].normalTexture.index >= 0;
      const PrimitiveData d = partPrimitive(scene.mesh, part.id, pm.uv, tangents);
      if (d.indices.empty()) continue;
      children.push_back(addMesh(model_, part.name, d, mat));
    }
    for (const Light* l : scene.lights.all()) {
      std::vector<Vec3f> v, n;
      l->shapes(&v, &n);
      if (v.empty()) continue;
      children.push_back(addShapeEmitter(*l, v, n));
      ++summary_.emitters;
    }

    tinygltf::Node root;
    root.name = "twin";
    root.children = children;
    const Vec3f up = scene.up.normalized();
    const Eigen::Quaternionf q = Eigen::Quaternionf::FromTwoVectors(up, Vec3f::UnitY());
    if (std::abs(q.w()) < 1.0f - 1e-7f) root.rotation = {q.x(), q.y(), q.z(), q.w()};
    model_.nodes.push_back(root);
    tinygltf::Scene gs;
    gs.name = "twin";
    gs.nodes = {static_cast<int>(model_.nodes.size()) - 1};
    model_.scenes.push_back(gs);
    model_.defaultScene = 0;
    model_.extensionsUsed.assign(extensions_.begin(), extensions_.end());

    summary_.meshes = static_cast<int>(model_.meshes.size());
    summary_.materials = static_cast<int>(model_.materials.size());
    summary_.images = static_cast<int>(model_.images.size());
    summary_.binBytes = model_.buffers[0].data.size();
    write();
    return summary_;
  }

 private:
  int textureFor(const fs::path& file) {
    const std::string uri = uriFor(file, outDir_);
    if (auto it = textureOfUri_.find(uri); it != textureOfUri_.end()) return it->second;
    tinygltf::Image img;
    img.uri = uri;
    img.name = file.stem().string();
    img.mimeType =
        file.extension() == ".jpg" || file.extension() == ".jpeg" ? "image/jpeg" : "image/png";
    model_.images.push_back(img);
    tinygltf::Texture tex;
    tex.sampler = 0;
    tex.source = static_cast<int>(model_.images.size()) - 1;
    tex.name = img.name;
    model_.textures.push_back(tex);
    const int id = static_cast<int>(model_.textures.size()) - 1;
    textureOfUri_[uri] = id;
    return id;
  }

  /// Map paths of a part's materials file (empty when the part has none).
  std::map<std::string, fs::path> mapFiles(const std::string& part) const {
    const fs::path mf = twin_.dir / "materials" / (part + ".json");
    if (!fs::exists(mf)) return {};
    return io::readMaterialJson(mf).maps;
  }

  int addPartMaterial(const Part& part, const PartMaterial& pm, bool window) {
    tinygltf::Material mat;
    mat.name = part.name;
    mat.doubleSided = options_.doubleSided;
    auto& pbr = mat.pbrMetallicRoughness;
    const std::map<std::string, fs::path> maps =
        pm.fromFile ? mapFiles(part.name) : std::map<std::string, fs::path>{};
    const fs::path texDir = outDir_ / "textures";

    // base color
    if (!pm.albedoMap.empty() && maps.count("albedo")) {
      const bool offset = !pm.albedoOffset.isZero();
      if (!offset && pm.albedoScale <= 1.0f) {
        pbr.baseColorTexture.index = textureFor(maps.at("albedo"));
        const double s = std::max(0.0f, pm.albedoScale);
        pbr.baseColorFactor = {s, s, s, 1.0};
      } else {
        const fs::path baked = texDir / (part.name + "_albedo_gltf.png");
        fs::create_directories(texDir);
        const FloatTexture& a = pm.albedoMap;
        io::writeImage(baked, makeImage(a.width(), a.height(), [&](int x, int y) {
                         return Vec3f((pm.albedoScale * (a.texel(x, y) + pm.albedoOffset))
                                          .cwiseMax(0.0f)
                                          .cwiseMin(1.0f));
                       }));
        pbr.baseColorTexture.index = textureFor(baked);
      }
    } else {
      pbr.baseColorFactor = {pm.albedo.x(), pm.albedo.y(), pm.albedo.z(), 1.0};
    }
    if (window) {
      mat.alphaMode = "BLEND";
      pbr.baseColorFactor = {pbr.baseColorFactor[0], pbr.baseColorFactor[1], pbr.baseColorFactor[2],
                             0.0};
    }

    // metallic (B) and roughness (G), packed
    const bool roughMap = !pm.roughnessMap.empty(), metalMap = !pm.metallicMap.empty();
    if (roughMap || metalMap) {
      const FloatTexture& ref = roughMap ? pm.roughnessMap : pm.metallicMap;
      const int w = ref.width(), h = ref.height();
      const fs::path packed = texDir / (part.name + "_metallic_roughness.png");
      fs::create_directories(texDir);
      io::WriteOptions wo;
      wo.encode = io::ColorSpace::Linear;
      io::writeImage(
          packed,
          makeImage(w, h,
                    [&](int x, int y) {
                      // texel centers in t of the reference map
                      const Vec2f t((x + 0.5f) / w, 1.0f - (y + 0.5f) / h);
                      const float r =
                          roughMap ? clampv(pm.roughnessScale * pm.roughnessMap.texel(x, y).x(),
                                            0.0f, 1.0f)
                                   : pm.roughness;
                      const float m =
                          metalMap ? clampv(pm.metallicMap.sample(t).x(), 0.0f, 1.0f) : pm.metallic;
                      return Vec3f(1.0f, r, m);
                    }),
          wo);
      pbr.metallicRoughnessTexture.index = textureFor(packed);
      pbr.roughnessFactor = 1.0;
      pbr.metallicFactor = 1.0;
    } else {
      pbr.roughnessFactor = clampv(pm.roughness, 0.0f, 1.0f);
      pbr.metallicFactor = clampv(pm.metallic, 0.0f, 1.0f);
    }

    // normal
    if (!pm.normalMap.empty() && maps.count("normal"))
      mat.normalTexture.index = textureFor(maps.at("normal"));

    // F0_dielectric = 0.08 * specular; glTF's default 0.04 is specular = 0.5
    if (std::abs(pm.specular - 0.5f) > 1e-6f) {
      const double f = 2.0 * pm.specular;
      tinygltf::Value::Object ext;
      ext["specularFactor"] = tinygltf::Value(std::min(1.0, f));
      if (f > 1.0) {
        tinygltf::Value::Array c(3, tinygltf::Value(f));
        ext["specularColorFactor"] = tinygltf::Value(c);
      }
      mat.extensions["KHR_materials_specular"] = tinygltf::Value(ext);
      extensions_.insert("KHR_materials_specular");
    }
    model_.materials.push_back(mat);
    return static_cast<int>(model_.materials.size()) - 1;
  }

  // An emitting surface a light adds (Light::shapes(): a rectangle's two triangles), vertices
  // shared where position and normal agree (a rectangle: its 4 corners, indices 0 1 2 0 2 3).
  int addShapeEmitter(const Light& l, const std::vector<Vec3f>& v, const std::vector<Vec3f>& n) {
    tinygltf::Material mat;
    mat.name = "emitter_" + l.label();
    mat.pbrMetallicRoughness.baseColorFactor = {0, 0, 0, 1};
    mat.pbrMetallicRoughness.metallicFactor = 0;
    mat.pbrMetallicRoughness.roughnessFactor = 1;
    setEmission(mat, l.scale().value_or(Vec3f::Ones()), extensions_);
    model_.materials.push_back(mat);
    const int matId = static_cast<int>(model_.materials.size()) - 1;

    PrimitiveData d;
    std::vector<std::pair<Vec3f, Vec3f>> unique;
    for (size_t k = 0; k < v.size(); ++k) {
      const Vec3f nk = k < n.size() ? n[k] : Vec3f(0, 1, 0);
      size_t idx = 0;
      while (idx < unique.size() && !(unique[idx].first == v[k] && unique[idx].second == nk)) ++idx;
      if (idx == unique.size()) {  // untextured: no UVs, no tangents
        unique.emplace_back(v[k], nk);
        d.positions.insert(d.positions.end(), {v[k].x(), v[k].y(), v[k].z()});
        d.normals.insert(d.normals.end(), {nk.x(), nk.y(), nk.z()});
      }
      d.indices.push_back(static_cast<uint32_t>(idx));
    }
    return addMesh(model_, "emitter_" + l.label(), d, matId);
  }

  static bool keepImageUri(const std::string*, const std::string*, const tinygltf::Image*, bool,
                           std::string*, void*) {
    return false;  // images are referenced by their uri, never embedded or rewritten
  }

  void write() {
    const std::string binName = options_.baseName + ".bin";
    std::vector<unsigned char> bin;
    bin.swap(model_.buffers[0].data);  // serialize without the (base64) data; the uri is set below
    tinygltf::TinyGLTF writer;
    writer.SetImageWriter(&GltfBuilder::keepImageUri, nullptr);
    std::ostringstream os;
    PS_Check(writer.WriteGltfSceneToStream(&model_, os, true, false),
             "tinygltf failed to serialize the twin");
    nlohmann::json j = nlohmann::json::parse(os.str());
    j["buffers"] = nlohmann::json::array({{{"byteLength", bin.size()}, {"uri", binName}}});
    fs::create_directories(outDir_);
    io::writeAtomically(outDir_ / binName, [&](const fs::path& tmp) {
      std::ofstream out(tmp, std::ios::binary);
      out.write(reinterpret_cast<const char*>(bin.data()),
                static_cast<std::streamsize>(bin.size()));
      PS_Check(out.good(), "cannot write " << tmp.string());
    });
    io::writeTextFile(outDir_ / (options_.baseName + ".gltf"), j.dump(1) + "\n");
    model_.buffers[0].data.swap(bin);
  }

  const Twin& twin_;
  fs::path outDir_;
  GltfExportOptions options_;
  tinygltf::Model model_;
  std::map<std::string, int> textureOfUri_;
  std::set<std::string> extensions_;
  GltfExportSummary summary_;
};

}  // namespace

GltfExportSummary writeTwinGltf(const Twin& twin, const fs::path& outDir,
                                const GltfExportOptions& options) {
  Timer timer;
  GltfBuilder builder(twin, outDir, options);
  const GltfExportSummary s = builder.build();
  spdlog::info(
      "glTF {}: {} meshes, {} materials, {} images, {} emitters, {:.1f} KiB binary ({:.2f}s)",
      (outDir / (options.baseName + ".gltf")).string(), s.meshes, s.materials, s.images, s.emitters,
      s.binBytes / 1024.0, timer.seconds());
  return s;
}

}  // namespace ps
