// Makes the bundled sample scene (samples/data/living-room) with the project's own tools: a
// furnished box room whose every part has a procedural material of the graph library with known
// parameters and UV transform, two ceiling lights of known radiance, a "photo" path-traced from
// that ground truth, the label image of the exact geometry, a coarse copy of the geometry (the
// furniture moved, turned and scaled by a few percent, as coarse CAD would be), a novel view and
// a relit view with their ground-truth renders.
//
//   ps_make_sample_scene OUT_FOLDER [--spp N] [--width W --height H] [--texture-size N]
//
// Outputs (paths relative to OUT_FOLDER):
//   scene.json            the input of `photoscene run` (view 0 = the photo; lights to fit)
//   room.obj              coarse geometry
//   room_exact.obj        the geometry the photo was rendered from
//   photos/view0.png      the photo (sRGB 8-bit)
//   segments/view0.png    16-bit labels (1000 + part)
//   cameras/novel0.json   a novel camera
//   lights_relit.json     the relit lights
//   gt/twin/              the ground truth in the output-folder format (render it: the photo)
//   gt/view0.exr, gt/novel0.{exr,png}, gt/relit0.{exr,png}   ground-truth renders

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "photoscene/core.hpp"
#include "photoscene/graph.hpp"
#include "photoscene/io.hpp"
#include "photoscene/raytrace.hpp"
#include "photoscene/scene.hpp"
#include "synthetic_obj.hpp"

namespace fs = std::filesystem;
using namespace ps;

namespace {

struct Box {
  std::string part;
  Vec3f lo, hi;
  int object;  ///< furniture object index (-1: the room)
};

/// Adds an axis-aligned box as 6 quads (12 triangles), counter-clockwise seen from outside
/// (inward = true: seen from inside, for the room).
void addBox(io::ObjMesh& m, const Box& b, bool inward, std::vector<int>* objectOfVertex) {
  const int mat = tools::materialIndex(m, b.part);
  const Vec3f& l = b.lo;
  const Vec3f& h = b.hi;
  const Vec3f c[8] = {{l.x(), l.y(), l.z()}, {h.x(), l.y(), l.z()}, {h.x(), h.y(), l.z()}, {l.x(), h.y(), l.z()},
                      {l.x(), l.y(), h.z()}, {h.x(), l.y(), h.z()}, {h.x(), h.y(), h.z()}, {l.x(), h.y(), h.z()}};
  // faces counter-clockwise seen from outside
  const int faces[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 4, 7, 3}, {1, 2, 6, 5}, {0, 1, 5, 4}, {3, 7, 6, 2}};
  for (const auto& f : faces) {
    auto corner = [&](int k) { return c[f[inward ? 3 - k : k]]; };
    tools::addQuad(m, {corner(0), corner(1), corner(2), corner(3)}, mat);
    objectOfVertex->insert(objectOfVertex->end(), 4, b.object);
  }
}

struct MaterialSpec {
  std::string part, graph;
  uint64_t seed;          ///< 0: the graph's defaults
  float rotationDeg, scale;
  Vec2f offset;
};

io::CameraDesc camera(int w, int h, double fovYDeg, const Vec3d& eye, const Vec3d& target) {
  return io::lookAtCamera(w, h, fovYDeg, eye, target);
}

nlohmann::json rectJson(const Vec3f& center, const Vec3f& u, const Vec3f& v) {
  return {{"center", {center.x(), center.y(), center.z()}}, {"edge_u", {u.x(), u.y(), u.z()}},
          {"edge_v", {v.x(), v.y(), v.z()}}};
}

}  // namespace

int main(int argc, char** argv) {
  initLogging();
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s OUT_FOLDER [--spp N] [--width W --height H] [--texture-size N]\n", argv[0]);
    return 2;
  }
  const fs::path out = argv[1];
  int spp = 1024, width = 320, height = 240, textureSize = 256;
  for (int i = 2; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    const int v = std::atoi(argv[i + 1]);
    if (a == "--spp") spp = v;
    else if (a == "--width") width = v;
    else if (a == "--height") height = v;
    else if (a == "--texture-size") textureSize = v;
  }
  fs::create_directories(out / "photos");
  fs::create_directories(out / "segments");
  fs::create_directories(out / "cameras");
  fs::create_directories(out / "gt/twin/materials");
  fs::create_directories(out / "gt/twin/textures");

  // ---- geometry: a 5 x 2.6 x 4 m room and its furniture
  const std::vector<Box> room = {{"room", {-2.5f, 0, -2}, {2.5f, 2.6f, 2}, -1}};
  const std::vector<Box> furniture = {
      {"sofa_fabric", {-1.6f, 0.0f, -1.95f}, {0.2f, 0.45f, -1.1f}, 0},
      {"sofa_fabric", {-1.6f, 0.45f, -1.95f}, {0.2f, 0.9f, -1.72f}, 0},
      {"sofa_fabric", {-1.6f, 0.45f, -1.72f}, {-1.4f, 0.65f, -1.1f}, 0},
      {"sofa_fabric", {0.0f, 0.45f, -1.72f}, {0.2f, 0.65f, -1.1f}, 0},
      {"rug", {-1.3f, 0.0f, -1.0f}, {0.9f, 0.012f, 0.7f}, 1},
      {"table_top", {-0.65f, 0.40f, -0.55f}, {0.45f, 0.44f, 0.15f}, 2},
      {"table_legs", {-0.62f, 0.012f, -0.52f}, {-0.57f, 0.40f, -0.47f}, 2},
      {"table_legs", {0.37f, 0.012f, -0.52f}, {0.42f, 0.40f, -0.47f}, 2},
      {"table_legs", {-0.62f, 0.012f, 0.07f}, {-0.57f, 0.40f, 0.12f}, 2},
      {"table_legs", {0.37f, 0.012f, 0.07f}, {0.42f, 0.40f, 0.12f}, 2},
      {"cabinet", {1.3f, 0.0f, -1.98f}, {2.4f, 0.95f, -1.45f}, 3},
  };
  io::ObjMesh exact;
  std::vector<int> objectOfVertex;
  {
    // the room: floor, ceiling and walls as separate parts
    const Box& r = room[0];
    io::ObjMesh tmp;
    std::vector<int> tmpObj;
    addBox(tmp, r, true, &tmpObj);
    const char* names[6] = {"wall_back", "wall_front", "wall_left", "wall_right", "floor", "ceiling"};
    for (size_t t = 0; t < tmp.triangles.size(); ++t) {
      const int mat = tools::materialIndex(exact, names[t / 2]);
      io::ObjCorner cs[3];
      for (int k = 0; k < 3; ++k) {
        exact.positions.push_back(tmp.positions[tmp.triangles[t][k].position]);
        objectOfVertex.push_back(-1);
        cs[k] = io::ObjCorner{static_cast<int>(exact.positions.size()) - 1, -1, -1};
      }
      exact.triangles.push_back({cs[0], cs[1], cs[2]});
      exact.triangleMaterial.push_back(mat);
      exact.triangleLine.push_back(0);
    }
  }
  for (const Box& b : furniture) addBox(exact, b, false, &objectOfVertex);

  // UVs in meters (planar per face cluster), written into the OBJ
  const std::vector<Part> parts = tools::writeUvsIntoObj(exact);
  io::writeObj(out / "room_exact.obj", exact);

  // coarse CAD: every furniture object moved 2-5 cm, turned 1-3 degrees about up, scaled 2-4 %
  io::ObjMesh coarse = exact;
  Rng rng(20221121);
  for (int object = 0; object < 4; ++object) {
    Eigen::AlignedBox3f box;
    for (size_t v = 0; v < coarse.positions.size(); ++v)
      if (objectOfVertex[v] == object) box.extend(coarse.positions[v]);
    const Vec3f c = box.center();
    const float angle = radians(rng.uniform(1.0f, 3.0f)) * (rng.uniform() < 0.5f ? -1 : 1);
    const float scale = 1.0f + rng.uniform(0.02f, 0.04f) * (rng.uniform() < 0.5f ? -1 : 1);
    const Vec3f shift(rng.uniform(-0.05f, 0.05f), 0, rng.uniform(-0.05f, 0.05f));
    const Eigen::Matrix3f R = Eigen::AngleAxisf(angle, Vec3f::UnitY()).toRotationMatrix();
    for (size_t v = 0; v < coarse.positions.size(); ++v) {
      if (objectOfVertex[v] != object) continue;
      Vec3f p = coarse.positions[v] - c;
      p = R * (scale * p);
      p.y() = (coarse.positions[v].y() - box.min().y()) * scale + box.min().y();  // stays on the floor
      coarse.positions[v] = Vec3f(c.x() + p.x(), p.y(), c.z() + p.z()) + shift;
    }
  }
  io::writeObj(out / "room.obj", coarse);

  // ---- materials: graphs with known parameters
  const std::vector<MaterialSpec> specs = {
      {"floor", "wood_planks", 11, 90.0f, 0.5f, {0.1f, 0.0f}},
      {"ceiling", "paint_matte_wall", 0, 0.0f, 0.5f, {0, 0}},
      {"wall_back", "paint_matte_wall", 0, 0.0f, 0.5f, {0, 0}},
      {"wall_front", "paint_matte_wall", 0, 0.0f, 0.5f, {0, 0}},
      {"wall_left", "wallpaper_stripes", 0, 0.0f, 1.0f, {0, 0}},
      {"wall_right", "plaster_smooth", 0, 0.0f, 0.5f, {0, 0}},
      {"rug", "carpet_patterned_rug", 0, 0.0f, 0.8f, {0.2f, 0.1f}},
      {"sofa_fabric", "fabric_twill", 0, 45.0f, 4.0f, {0, 0}},
      {"table_top", "wood_veneer", 0, 0.0f, 1.2f, {0, 0}},
      {"table_legs", "metal_painted", 0, 0.0f, 2.0f, {0, 0}},
      {"cabinet", "wood_painted", 0, 90.0f, 1.0f, {0, 0}},
  };
  const GraphLibrary library = GraphLibrary::load();
  for (const MaterialSpec& s : specs) {
    MaterialGraph g = library.create(s.graph);
    if (s.seed) g.setValues(g.randomValues(s.seed, 0.3f));
    const MaterialMaps maps = g.evaluate(textureSize, MapSet::all());
    const fs::path tex = out / "gt/twin/textures";
    io::writeImage(tex / (s.part + "_albedo.png"), maps.albedo);
    cv::Mat n;
    maps.normal.convertTo(n, CV_32F, 0.5, 0.5);
    io::WriteOptions linear;
    linear.encode = io::ColorSpace::Linear;
    io::writeImage(tex / (s.part + "_normal.png"), n, linear);
    io::writeImage(tex / (s.part + "_roughness.png"), maps.roughness, linear);
    io::MaterialFileDesc m;
    m.part = s.part;
    m.graph = s.graph;
    m.category = g.category();
    nlohmann::json params = nlohmann::json::object();
    for (const GraphParameter& p : g.parameters()) {
      const std::vector<float> v = g.parameter(p.name);
      params[p.name] = v.size() == 1 ? nlohmann::json(v[0]) : nlohmann::json(v);
    }
    m.params = params;
    m.uv.rotationDeg = s.rotationDeg;
    m.uv.scale = Vec2d::Constant(s.scale);
    m.uv.offset = s.offset.cast<double>();
    const cv::Scalar mean = cv::mean(maps.albedo);
    m.homogeneous.albedo = Vec3d(mean[0], mean[1], mean[2]);
    m.homogeneous.roughness = cv::mean(maps.roughness)[0];
    m.maps["albedo"] = tex / (s.part + "_albedo.png");
    m.maps["normal"] = tex / (s.part + "_normal.png");
    m.maps["roughness"] = tex / (s.part + "_roughness.png");
    m.skipped = "ground truth (not fitted)";
    io::writeMaterialJson(out / "gt/twin/materials" / (s.part + ".json"), m, out / "gt/twin");
  }

  // ---- lights and cameras
  const Vec3f l0c(-0.8f, 2.59f, -0.6f), l1c(1.2f, 2.59f, 0.8f);
  const Vec3f l0u(0.6f, 0, 0), l0v(0, 0, 0.6f), l1u(0.4f, 0, 0), l1v(0, 0, 0.8f);  // x cross z = -y: down
  const Vec3d radiance0(20.0, 18.5, 16.0), radiance1(16.0, 16.0, 18.0);
  auto lightsFile = [&](const Vec3d& r0, const Vec3d& r1) {
    io::LightsFileDesc l;
    io::AreaLightDesc a, b;
    a.name = "ceiling_0";
    a.center = l0c.cast<double>();
    a.edgeU = l0u.cast<double>();
    a.edgeV = l0v.cast<double>();
    a.radiance = r0;
    b.name = "ceiling_1";
    b.center = l1c.cast<double>();
    b.edgeU = l1u.cast<double>();
    b.edgeV = l1v.cast<double>();
    b.radiance = r1;
    l.emitters = {a, b};
    l.exposure = {1.0};
    return l;
  };
  io::writeLightsJson(out / "gt/twin/lights.json", lightsFile(radiance0, radiance1));
  io::writeLightsJson(out / "lights_relit.json", lightsFile(Vec3d(6, 9, 16), Vec3d(30, 20, 10)));
  const io::CameraDesc view0 = camera(width, height, 62, Vec3d(-2.1, 1.55, 1.75), Vec3d(0.4, 0.55, -1.3));
  const io::CameraDesc novel0 = camera(width, height, 58, Vec3d(2.0, 1.4, 1.6), Vec3d(-0.8, 0.5, -1.2));
  io::writeJsonFile(out / "cameras/novel0.json", io::cameraToJson(novel0));

  nlohmann::json lightsJson = {{"area", {rectJson(l0c, l0u, l0v), rectJson(l1c, l1u, l1v)}}};
  nlohmann::json gtLights = lightsJson;
  gtLights["area"][0]["radiance"] = {radiance0.x(), radiance0.y(), radiance0.z()};
  gtLights["area"][1]["radiance"] = {radiance1.x(), radiance1.y(), radiance1.z()};
  // segment_parts pins the parts the photo shows (filled in once the labels are rendered)
  nlohmann::json segmentParts = nlohmann::json::object();
  const nlohmann::json viewJson = {{"image", "photos/view0.png"}, {"color_space", "srgb"},
                                   {"camera", io::cameraToJson(view0)}, {"segments", "segments/view0.png"},
                                   {"segment_parts", segmentParts}};
  auto writeTwinScene = [&](const nlohmann::json& pinned) {
    nlohmann::json twinView = viewJson;
    twinView["image"] = "../../photos/view0.png";
    twinView["segments"] = "../../segments/view0.png";
    twinView["segment_parts"] = pinned;
    io::writeJsonFile(out / "gt/twin/scene.json", {{"version", 1}, {"geometry", "../../room_exact.obj"},
                                                    {"up", {0, 1, 0}}, {"views", {twinView}}, {"lights", gtLights},
                                                    {"options", {{"preset", "balanced"}, {"seed", 0}}}});
  };
  writeTwinScene(segmentParts);

  // ---- the photo, the labels, the ground-truth renders
  // a placeholder photo of the right size lets loadTwin validate the scene before the real one exists
  io::writeImage(out / "photos/view0.png", cv::Mat(height, width, CV_32FC3, cv::Scalar(0, 0, 0)));
  io::writeRawImage(out / "segments/view0.png", cv::Mat(height, width, CV_16UC1, cv::Scalar(0)));
  const Twin twin = loadTwin(out / "gt/twin");
  const PathTracer tracer(twin.scene, twin.materials);
  RenderOptions ro;
  ro.spp = spp;
  ro.seed = 1;
  const Camera cam0 = Camera::fromDesc(view0), camN = Camera::fromDesc(novel0);
  const cv::Mat photo = tracer.render(cam0, ro);
  io::WriteOptions f32;
  f32.bits = 16;
  io::writeImage(out / "gt/view0.exr", photo, f32);
  io::writeImage(out / "photos/view0.png", photo);
  const GBuffer gb = renderGBuffer(tracer, cam0);
  cv::Mat labels(gb.partId.size(), CV_16UC1, cv::Scalar(0));
  for (int y = 0; y < labels.rows; ++y)
    for (int x = 0; x < labels.cols; ++x) {
      const int p = gb.partId.at<int>(y, x);
      if (p >= 0) labels.at<uint16_t>(y, x) = static_cast<uint16_t>(1000 + p);
    }
  io::writeRawImage(out / "segments/view0.png", labels);
  for (const Part& p : parts)
    if (cv::countNonZero(labels == 1000 + p.id) > 0) segmentParts[std::to_string(1000 + p.id)] = p.name;
  writeTwinScene(segmentParts);
  const cv::Mat novel = tracer.render(camN, ro);
  io::writeImage(out / "gt/novel0.exr", novel, f32);
  io::writeImage(out / "gt/novel0.png", novel);

  // relit: the same twin under lights_relit.json
  Twin relit = loadTwin(out / "gt/twin");
  relit.scene.lights = makeLights(io::readLightsJson(out / "lights_relit.json"), relit.scene.mesh, relit.scene.parts,
                                  relit.scene.up, (out / "lights_relit.json").string());
  const PathTracer relitTracer(relit.scene, relit.materials);
  const cv::Mat relitImg = relitTracer.render(cam0, ro);
  io::writeImage(out / "gt/relit0.exr", relitImg, f32);
  io::writeImage(out / "gt/relit0.png", relitImg);

  // ---- the input scene.json: coarse geometry, lights to fit
  nlohmann::json inputView = viewJson;
  inputView["segment_parts"] = segmentParts;
  io::writeJsonFile(out / "scene.json", {{"version", 1}, {"geometry", "room.obj"}, {"up", {0, 1, 0}},
                                         {"views", {inputView}}, {"lights", lightsJson},
                                         {"options", {{"preset", "balanced"}, {"seed", 0}}}});
  spdlog::info("sample scene written to {}", out.string());
  return 0;
}
