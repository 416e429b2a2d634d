// glTF export of a twin: what a glTF reader (tinygltf, Blender) gets back.
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>

#include "photoscene/core.hpp"
#include "photoscene/io.hpp"
#include "photoscene/scene.hpp"

namespace ps {
namespace {

using io::TempDir;

/// A tiny twin folder: floor (maps, rotated/scaled UVs, albedo_scale 0.8, roughness_scale 0.5),
/// wall (homogeneous, metallic, specular 0.25), box (albedo map with an offset: baked), lamp (no
/// materials file, an OBJ-part emitter), window (an environment opening), one rectangle emitter.
struct TinyTwin {
  TempDir dir{"ps_gltf"};
  TinyTwin() {
    const fs::path d = dir.path();
    io::writeTextFile(d / "room.obj", R"(# tiny twin
v -3 0 -2
v 3 0 -2
v 3 0 2
v -3 0 2
v -3 0 -2
v 3 0 -2
v 3 2.7 -2
v -3 2.7 -2
v -0.2 2.6 -0.2
v 0.2 2.6 -0.2
v 0.2 2.6 0.2
v -0.2 2.6 0.2
v -1 1 -1.99
v 1 1 -1.99
v 1 2 -1.99
v -1 2 -1.99
v 1 0.5 0
v 2 0.5 0
v 2 0.5 1
v 1 0.5 1
vt 0 0
vt 1 0
vt 1 1
vt 0 1
vn 0 1 0
vn 0 0 1
vn 0 -1 0
usemtl floor
f 4/1/1 3/2/1 2/3/1 1/4/1
usemtl wall
f 5/1/2 6/2/2 7/3/2 8/4/2
usemtl lamp
f 9/1/3 10/2/3 11/3/3 12/4/3
usemtl window
f 13/1/2 14/2/2 15/3/2 16/4/2
usemtl box
f 20/1/1 19/2/1 18/3/1 17/4/1
)");
    fs::create_directories(d / "photos");
    io::writeImage(d / "photos/view0.png", cv::Mat(48, 64, CV_32FC3, cv::Scalar(0.3, 0.3, 0.3)));
    const Mat4d w2c =
        io::lookAtWorldToCamera(Vec3d(0, 1.5, 1.8), Vec3d(0, 0.5, -1), Vec3d(0, 1, 0));
    const io::CameraDesc cam{64, 48, 50, 50, 31.5, 23.5, w2c};
    nlohmann::json scene = {
        {"version", 1},
        {"geometry", "room.obj"},
        {"views", {{{"image", "photos/view0.png"}, {"camera", io::cameraToJson(cam)}}}},
        {"lights",
         {{"area",
           {{{"part", "lamp"}, {"radiance", {5.0, 4.0, 3.0}}},
            {{"center", {0, 2.69, 1}},
             {"edge_u", {0.4, 0, 0}},
             {"edge_v", {0, 0, 0.4}},
             {"radiance", {0.5, 0.25, 0.125}}}}},
          {"environment", {{"window_parts", {"window"}}}}}}};
    io::writeJsonFile(d / "scene.json", scene);

    fs::create_directories(d / "textures");
    cv::Mat albedo(8, 8, CV_32FC3);
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 8; ++x) albedo.at<cv::Vec3f>(y, x) = cv::Vec3f(x / 7.0f, y / 7.0f, 0.25f);
    io::writeImage(d / "textures/floor_albedo.png", albedo);
    io::WriteOptions lin;
    lin.encode = io::ColorSpace::Linear;
    io::writeImage(d / "textures/floor_normal.png",
                   cv::Mat(8, 8, CV_32FC3, cv::Scalar(0.5, 0.5, 1.0)), lin);
    io::writeImage(d / "textures/floor_roughness.png", cv::Mat(8, 8, CV_32FC1, cv::Scalar(0.6)),
                   lin);
    io::writeImage(d / "textures/box_albedo.png",
                   cv::Mat(4, 4, CV_32FC3, cv::Scalar(0.2, 0.2, 0.2)));

    fs::create_directories(d / "materials");
    io::writeJsonFile(
        d / "materials/floor.json",
        {{"part", "floor"},
         {"graph", "wood_planks"},
         {"category", "wood"},
         {"uv_transform", {{"rotation_deg", 30.0}, {"scale", {2.0, 3.0}}, {"offset", {0.1, 0.2}}}},
         {"albedo_scale", 0.8},
         {"roughness_scale", 0.5},
         {"maps",
          {{"albedo", "textures/floor_albedo.png"},
           {"normal", "textures/floor_normal.png"},
           {"roughness", "textures/floor_roughness.png"}}}});
    io::writeJsonFile(d / "materials/wall.json", {{"part", "wall"},
                                                  {"graph", "homogeneous"},
                                                  {"category", "homogeneous"},
                                                  {"homogeneous",
                                                   {{"albedo", {0.6, 0.5, 0.4}},
                                                    {"roughness", 0.9},
                                                    {"metallic", 0.2},
                                                    {"specular", 0.25}}}});
    io::writeJsonFile(d / "materials/box.json",
                      {{"part", "box"},
                       {"graph", "paint_plain"},
                       {"category", "paint"},
                       {"albedo_offset", {0.1, 0.0, 0.0}},
                       {"maps", {{"albedo", "textures/box_albedo.png"}}}});
  }
};

tinygltf::Model loadGltf(const fs::path& file) {
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string err, warn;
  const bool ok = loader.LoadASCIIFromFile(&model, &err, &warn, file.string());
  EXPECT_TRUE(ok) << err;
  EXPECT_TRUE(err.empty()) << err;
  return model;
}

const tinygltf::Material* materialNamed(const tinygltf::Model& m, const std::string& name) {
  for (const auto& mat : m.materials)
    if (mat.name == name) return &mat;
  return nullptr;
}

const tinygltf::Mesh* meshNamed(const tinygltf::Model& m, const std::string& name) {
  for (const auto& mesh : m.meshes)
    if (mesh.name == name) return &mesh;
  return nullptr;
}

/// Float attribute values of an accessor (tightly packed, as the exporter writes them).
std::vector<float> floats(const tinygltf::Model& m, int accessor) {
  const auto& acc = m.accessors[accessor];
  const auto& view = m.bufferViews[acc.bufferView];
  const auto& buf = m.buffers[view.buffer];
  const int comps = tinygltf::GetNumComponentsInType(acc.type);
  std::vector<float> out(acc.count * comps);
  std::memcpy(out.data(), buf.data.data() + view.byteOffset + acc.byteOffset,
              out.size() * sizeof(float));
  return out;
}

double emissiveStrength(const tinygltf::Material& mat) {
  auto it = mat.extensions.find("KHR_materials_emissive_strength");
  if (it == mat.extensions.end()) return 1.0;
  return it->second.Get("emissiveStrength").GetNumberAsDouble();
}

TEST(Scene_GltfExport, tiny_twin_round_trips_through_tinygltf) {
  TinyTwin t;
  const Twin twin = loadTwin(t.dir.path());
  const GltfExportSummary s = writeTwinGltf(twin, t.dir.path());
  ASSERT_TRUE(fs::exists(t.dir / "twin.gltf"));
  ASSERT_TRUE(fs::exists(t.dir / "twin.bin"));
  // no temporary files left behind
  for (const auto& e : fs::directory_iterator(t.dir.path()))
    EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();

  const tinygltf::Model m = loadGltf(t.dir / "twin.gltf");
  // one material per part (window left out) + one per rectangle emitter
  EXPECT_EQ(twin.scene.parts.size(), 5u);
  EXPECT_EQ(m.materials.size(), 4u + 1u);
  EXPECT_EQ(s.materials, 5);
  for (const char* p : {"floor", "wall", "lamp", "box"}) {
    EXPECT_NE(materialNamed(m, p), nullptr) << p;
    EXPECT_NE(meshNamed(m, p), nullptr) << p;
  }
  EXPECT_EQ(materialNamed(m, "window"), nullptr);
  EXPECT_EQ(meshNamed(m, "window"), nullptr);

  // every image resolves to a file of the folder, and tinygltf decoded it
  ASSERT_FALSE(m.images.empty());
  for (const auto& img : m.images) {
    EXPECT_TRUE(fs::exists(t.dir / img.uri)) << img.uri;
    EXPECT_GT(img.width, 0) << img.uri;
  }

  // floor: textures and factors
  const tinygltf::Material& floor = *materialNamed(m, "floor");
  const auto& pbr = floor.pbrMetallicRoughness;
  ASSERT_GE(pbr.baseColorTexture.index, 0);
  EXPECT_EQ(m.images[m.textures[pbr.baseColorTexture.index].source].uri,
            "textures/floor_albedo.png");
  EXPECT_NEAR(pbr.baseColorFactor[0], 0.8, 1e-6);  // pure albedo_scale <= 1: a factor
  ASSERT_GE(floor.normalTexture.index, 0);
  EXPECT_EQ(m.images[m.textures[floor.normalTexture.index].source].uri,
            "textures/floor_normal.png");
  ASSERT_GE(pbr.metallicRoughnessTexture.index, 0);
  EXPECT_EQ(m.images[m.textures[pbr.metallicRoughnessTexture.index].source].uri,
            "textures/floor_metallic_roughness.png");
  const cv::Mat mr = io::readDataImage(t.dir / "textures/floor_metallic_roughness.png");
  ASSERT_EQ(mr.channels(), 3);
  EXPECT_NEAR(mr.at<cv::Vec3f>(3, 3)[1], 0.6 * 0.5, 1.0 / 255);  // G: roughness * roughness_scale
  EXPECT_NEAR(mr.at<cv::Vec3f>(3, 3)[2], 0.0, 1.0 / 255);        // B: metallic
  for (const auto& sm : m.samplers) {
    EXPECT_EQ(sm.wrapS, TINYGLTF_TEXTURE_WRAP_REPEAT);
    EXPECT_EQ(sm.wrapT, TINYGLTF_TEXTURE_WRAP_REPEAT);
  }

  // floor geometry: 4 distinct corners, 2 triangles; UVs are the transformed t with v flipped
  const auto& fprim = meshNamed(m, "floor")->primitives.at(0);
  EXPECT_EQ(m.accessors[fprim.indices].count, 6u);
  const std::vector<float> pos = floats(m, fprim.attributes.at("POSITION"));
  const std::vector<float> uv = floats(m, fprim.attributes.at("TEXCOORD_0"));
  const std::vector<float> tan = floats(m, fprim.attributes.at("TANGENT"));
  ASSERT_EQ(pos.size() / 3, 4u);
  const UvTransform& uvt = twin.materials[twin.scene.partId("floor")].uv;
  const std::map<std::pair<int, int>, Vec2f> objUv = {{{-3, 2}, Vec2f(0, 0)},
                                                      {{3, 2}, Vec2f(1, 0)},
                                                      {{3, -2}, Vec2f(1, 1)},
                                                      {{-3, -2}, Vec2f(0, 1)}};
  for (size_t v = 0; v < 4; ++v) {
    const auto key = std::make_pair(static_cast<int>(std::lround(pos[3 * v])),
                                    static_cast<int>(std::lround(pos[3 * v + 2])));
    ASSERT_TRUE(objUv.count(key));
    const Vec2f tt = uvt.apply(objUv.at(key));
    EXPECT_NEAR(uv[2 * v], tt.x(), 1e-5);
    EXPECT_NEAR(uv[2 * v + 1], 1.0f - tt.y(), 1e-5);
    // tangent along dP/dt_u; normal x tangent along dP/dt_v (OpenGL convention)
    const Vec3f T(tan[4 * v], tan[4 * v + 1], tan[4 * v + 2]);
    const Vec3f B = Vec3f(0, 1, 0).cross(T) * tan[4 * v + 3];
    // dP/dt = dP/duv * M^-1
    const Eigen::Matrix2f Mi = uvt.linear().inverse();
    const Vec3f dPdu(6, 0, 0), dPdv(0, 0, -4);  // the 6 x 4 m floor spans uv [0, 1]^2
    const Vec3f dPdtu = (dPdu * Mi(0, 0) + dPdv * Mi(1, 0)).normalized();
    const Vec3f dPdtv = dPdu * Mi(0, 1) + dPdv * Mi(1, 1);
    EXPECT_NEAR(T.dot(dPdtu), 1.0f, 1e-4);
    EXPECT_GT(B.dot(dPdtv), 0.0f);
  }

  // every part's vertices and indices match the mesh
  size_t indexTotal = 0;
  for (const Part& p : twin.scene.parts) {
    if (p.name == "window") continue;
    const auto& prim = meshNamed(m, p.name)->primitives.at(0);
    EXPECT_EQ(m.accessors[prim.indices].count, 3u * p.triangleCount) << p.name;
    EXPECT_EQ(m.accessors[prim.attributes.at("POSITION")].count, 4u) << p.name;  // quads
    indexTotal += m.accessors[prim.indices].count;
  }
  EXPECT_EQ(indexTotal, 3u * (twin.scene.mesh.numTriangles() - 2));  // less the window's 2

  // wall: homogeneous factors, specular 0.25 -> KHR_materials_specular factor 0.5
  const tinygltf::Material& wall = *materialNamed(m, "wall");
  EXPECT_NEAR(wall.pbrMetallicRoughness.baseColorFactor[0], 0.6, 1e-6);
  EXPECT_NEAR(wall.pbrMetallicRoughness.roughnessFactor, 0.9, 1e-6);
  EXPECT_NEAR(wall.pbrMetallicRoughness.metallicFactor, 0.2, 1e-6);
  EXPECT_EQ(wall.pbrMetallicRoughness.baseColorTexture.index, -1);
  ASSERT_TRUE(wall.extensions.count("KHR_materials_specular"));
  EXPECT_NEAR(
      wall.extensions.at("KHR_materials_specular").Get("specularFactor").GetNumberAsDouble(), 0.5,
      1e-6);

  // box: albedo offset baked into its own texture
  const tinygltf::Material& box = *materialNamed(m, "box");
  ASSERT_GE(box.pbrMetallicRoughness.baseColorTexture.index, 0);
  const std::string boxUri =
      m.images[m.textures[box.pbrMetallicRoughness.baseColorTexture.index].source].uri;
  EXPECT_EQ(boxUri, "textures/box_albedo_gltf.png");
  const cv::Mat baked = io::readImage(t.dir / boxUri);
  EXPECT_NEAR(baked.at<cv::Vec3f>(1, 1)[0], 0.3, 0.01);
  EXPECT_NEAR(baked.at<cv::Vec3f>(1, 1)[1], 0.2, 0.01);

  // emitters: the lamp part (gray default + emission) and the rectangle
  EXPECT_EQ(s.emitters, 2);
  int emissive = 0;
  for (const auto& mat : m.materials)
    if (mat.emissiveFactor.size() == 3 && (mat.emissiveFactor[0] > 0 || mat.emissiveFactor[1] > 0))
      ++emissive;
  EXPECT_EQ(emissive, 2);
  const tinygltf::Material& lamp = *materialNamed(m, "lamp");
  EXPECT_NEAR(lamp.pbrMetallicRoughness.baseColorFactor[0], 0.5, 1e-6);
  EXPECT_NEAR(lamp.pbrMetallicRoughness.roughnessFactor, 0.7, 1e-6);
  const double ls = emissiveStrength(lamp);
  EXPECT_NEAR(lamp.emissiveFactor[0] * ls, 5.0, 1e-5);
  EXPECT_NEAR(lamp.emissiveFactor[1] * ls, 4.0, 1e-5);
  EXPECT_NEAR(lamp.emissiveFactor[2] * ls, 3.0, 1e-5);
  const tinygltf::Material* rect = nullptr;
  for (const auto& mat : m.materials)
    if (mat.name.rfind("emitter_", 0) == 0) rect = &mat;
  ASSERT_NE(rect, nullptr);
  EXPECT_FALSE(rect->extensions.count("KHR_materials_emissive_strength"));  // radiance <= 1
  EXPECT_NEAR(rect->emissiveFactor[0], 0.5, 1e-6);
  EXPECT_NEAR(rect->emissiveFactor[2], 0.125, 1e-6);
  const tinygltf::Mesh* rectMesh = nullptr;
  for (const auto& mesh : m.meshes)
    if (mesh.name.rfind("emitter_", 0) == 0) rectMesh = &mesh;
  ASSERT_NE(rectMesh, nullptr);
  const auto& rp = rectMesh->primitives.at(0);
  const std::vector<float> rpos = floats(m, rp.attributes.at("POSITION"));
  const std::vector<float> rn = floats(m, rp.attributes.at("NORMAL"));
  ASSERT_EQ(rpos.size(), 12u);
  EXPECT_NEAR(rn[1], -1.0f, 1e-6);  // x cross z = -y: facing down
  // the triangles' winding agrees with the normal
  const Vec3f a(rpos[0], rpos[1], rpos[2]), b(rpos[3], rpos[4], rpos[5]),
      c(rpos[6], rpos[7], rpos[8]);
  EXPECT_LT((b - a).cross(c - a).y(), 0.0f);
  EXPECT_TRUE(std::find(m.extensionsUsed.begin(), m.extensionsUsed.end(),
                        "KHR_materials_emissive_strength") != m.extensionsUsed.end());
}

TEST(Scene_GltfExport, window_parts_can_be_kept_transparent) {
  TinyTwin t;
  const Twin twin = loadTwin(t.dir.path());
  GltfExportOptions o;
  o.includeWindowParts = true;
  o.baseName = "with_windows";
  writeTwinGltf(twin, t.dir.path(), o);
  const tinygltf::Model m = loadGltf(t.dir / "with_windows.gltf");
  const tinygltf::Material* w = materialNamed(m, "window");
  ASSERT_NE(w, nullptr);
  EXPECT_EQ(w->alphaMode, "BLEND");
  EXPECT_EQ(w->pbrMetallicRoughness.baseColorFactor[3], 0.0);
}

/// The bundled ground-truth twin (samples/data/living-room/gt/twin), copied with what its
/// scene.json names (../../room_exact.obj, photos, segments).
fs::path copySampleTwin(const TempDir& dir) {
  const fs::path src = fs::path(PS_SOURCE_DIR) / "samples/data/living-room";
  const fs::path dst = dir / "living-room";
  fs::create_directories(dst);
  fs::copy(src, dst, fs::copy_options::recursive);
  return dst / "gt/twin";
}

TEST(Scene_GltfExport, sample_twin_exports_every_part_with_its_maps) {
  TempDir dir("ps_gltf_sample");
  const fs::path twinDir = copySampleTwin(dir);
  const Twin twin = loadTwin(twinDir);
  writeTwinGltf(twin, twinDir);
  const tinygltf::Model m = loadGltf(twinDir / "twin.gltf");
  size_t parts = 0, emitters = 0;
  for (const Part& p : twin.scene.parts) {
    const tinygltf::Material* mat = materialNamed(m, p.name);
    ASSERT_NE(mat, nullptr) << p.name;
    ++parts;
    if (twin.materials[p.id].albedoMap.empty()) continue;
    EXPECT_GE(mat->pbrMetallicRoughness.baseColorTexture.index, 0) << p.name;
    EXPECT_GE(mat->normalTexture.index, 0) << p.name;
    EXPECT_GE(mat->pbrMetallicRoughness.metallicRoughnessTexture.index, 0) << p.name;
  }
  for (const auto& mat : m.materials)
    if (mat.name.rfind("emitter_", 0) == 0) ++emitters;
  EXPECT_EQ(m.materials.size(), parts + emitters);
  EXPECT_EQ(emitters, twin.scene.lights.area.size());
  for (const auto& img : m.images) {
    EXPECT_TRUE(fs::exists(twinDir / img.uri)) << img.uri;
    EXPECT_GT(img.width, 0);
  }
  size_t indices = 0;
  for (const Part& p : twin.scene.parts)
    indices += m.accessors[meshNamed(m, p.name)->primitives.at(0).indices].count;
  EXPECT_EQ(indices, 3 * twin.scene.mesh.numTriangles());
}

std::string runCapture(const std::string& cmd, int* status) {
  std::string out;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) {
    *status = -1;
    return out;
  }
  std::array<char, 4096> buf{};
  while (size_t n = fread(buf.data(), 1, buf.size(), p)) out.append(buf.data(), n);
  *status = pclose(p);
  return out;
}

TEST(Scene_GltfExport, blender_imports_the_materials_and_images) {
  int status = 0;
  runCapture("command -v blender >/dev/null 2>&1", &status);
  if (status != 0) GTEST_SKIP() << "blender is not on PATH";
  TinyTwin t;
  const Twin twin = loadTwin(t.dir.path());
  writeTwinGltf(twin, t.dir.path());
  const std::string script =
      "import bpy\n"
      "try:\n"  // Blender 3.4's importer uses np.bool, removed in NumPy 1.24
      "    import numpy\n"
      "    if not hasattr(numpy, 'bool'): numpy.bool = bool\n"
      "except ImportError:\n"
      "    pass\n"
      "bpy.ops.wm.read_factory_settings(use_empty=True)\n"
      "bpy.ops.import_scene.gltf(filepath=r'" +
      (t.dir / "twin.gltf").string() +
      "')\n"
      "mats = sorted(m.name for m in bpy.data.materials)\n"
      "imgs = [i for i in bpy.data.images if i.size[0] > 0]\n"
      "print('PS_MATERIALS', len(mats), ','.join(mats))\n"
      "print('PS_IMAGES', len(imgs))\n";
  io::writeTextFile(t.dir / "import.py", script);
  const std::string out = runCapture(
      "blender -b --factory-startup --python " + (t.dir / "import.py").string() + " 2>&1", &status);
  if (out.find("No module named") != std::string::npos)
    GTEST_SKIP() << "Blender's glTF importer cannot load (python3-numpy missing?)";
  ASSERT_EQ(status, 0) << out;
  auto number = [&](const std::string& key) {
    const size_t p = out.find(key + " ");
    if (p == std::string::npos) return -1;
    return std::atoi(out.c_str() + p + key.size() + 1);
  };
  EXPECT_EQ(number("PS_MATERIALS"), 5) << out;
  // floor albedo, normal, metallic-roughness; box baked albedo
  EXPECT_EQ(number("PS_IMAGES"), 4) << out;
}

}  // namespace
}  // namespace ps
