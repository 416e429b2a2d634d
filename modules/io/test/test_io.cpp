#include <gtest/gtest.h>

#include <fstream>

#include "photoscene/core.hpp"
#include "photoscene/io.hpp"
#include "input_error_of.hpp"

namespace ps::io {
namespace {

void writeText(const fs::path& p, const std::string& s) {
  std::ofstream(p) << s;
}

using test::contains;
using test::inputErrorOf;


TEST(Io_Image, png8_round_trip_within_one_level) {
  TempDir dir;
  cv::Mat lin(8, 32, CV_32FC3);
  Rng rng(1);
  for (int y = 0; y < lin.rows; ++y)
    for (int x = 0; x < lin.cols; ++x) lin.at<cv::Vec3f>(y, x) = cv::Vec3f(rng.uniform(), rng.uniform(), rng.uniform());
  writeImage(dir / "a.png", lin);
  const cv::Mat back = readImage(dir / "a.png");
  ASSERT_EQ(back.type(), CV_32FC3);
  ASSERT_EQ(back.size(), lin.size());
  const cv::Mat encA = linearToSrgb(lin, CV_32F), encB = linearToSrgb(back, CV_32F);
  EXPECT_LE(cv::norm(encA, encB, cv::NORM_INF), 0.5 / 255 + 1e-6);
  // RGB order is kept (not BGR): a red pixel stays red
  cv::Mat red(1, 1, CV_32FC3, cv::Scalar(1, 0, 0));
  writeImage(dir / "red.png", red);
  EXPECT_NEAR(readImage(dir / "red.png").at<cv::Vec3f>(0, 0)[0], 1.0f, 1e-6);
  EXPECT_NEAR(readImage(dir / "red.png").at<cv::Vec3f>(0, 0)[2], 0.0f, 1e-6);
}

TEST(Io_Image, png16_and_exr_round_trip) {
  TempDir dir;
  cv::Mat lin(4, 4, CV_32FC3, cv::Scalar(0.25, 0.5, 2.5));
  WriteOptions o16;
  o16.bits = 16;
  writeImage(dir / "a.png", lin, o16);
  EXPECT_EQ(readImageInfo(dir / "a.png").bitsPerChannel, 16);
  cv::Mat b = readImage(dir / "a.png");
  EXPECT_NEAR(b.at<cv::Vec3f>(0, 0)[1], 0.5f, 1e-4);
  EXPECT_NEAR(b.at<cv::Vec3f>(0, 0)[2], 1.0f, 1e-6);  // clamped by the 16-bit encode
  WriteOptions f32;
  f32.bits = 32;
  writeImage(dir / "a.exr", lin, f32);
  cv::Mat e = readImage(dir / "a.exr");
  EXPECT_FLOAT_EQ(e.at<cv::Vec3f>(3, 3)[2], 2.5f);  // linear, unclamped
  writeImage(dir / "h.exr", lin);                   // half by default
  EXPECT_NEAR(readImage(dir / "h.exr").at<cv::Vec3f>(0, 0)[0], 0.25f, 1e-3);
  // linear storage for data maps
  WriteOptions linear;
  linear.encode = ColorSpace::Linear;
  cv::Mat rough(2, 2, CV_32FC1, cv::Scalar(0.3));
  writeImage(dir / "r.png", rough, linear);
  cv::Mat r = readDataImage(dir / "r.png");
  ASSERT_EQ(r.type(), CV_32FC1);
  EXPECT_NEAR(r.at<float>(0, 0), 0.3f, 0.5 / 255);
  // a linear-tagged 8-bit photo is not decoded
  cv::Mat gray(2, 2, CV_32FC1, cv::Scalar(0.5));
  writeImage(dir / "g.png", gray, linear);
  EXPECT_NEAR(readImage(dir / "g.png", ColorSpace::Linear).at<cv::Vec3f>(0, 0)[1], 128 / 255.f, 1e-6);
  EXPECT_NEAR(readImage(dir / "g.png", ColorSpace::SRGB).at<cv::Vec3f>(0, 0)[1], srgbToLinear(128 / 255.f), 1e-6);
}

TEST(Io_Image, labels_and_errors) {
  TempDir dir;
  cv::Mat labels(3, 3, CV_16UC1, cv::Scalar(1000));
  labels.at<uint16_t>(1, 1) = 65535;
  writeRawImage(dir / "l.png", labels);
  cv::Mat l = readLabelImage(dir / "l.png");
  ASSERT_EQ(l.type(), CV_32SC1);
  EXPECT_EQ(l.at<int>(1, 1), 65535);
  EXPECT_EQ(l.at<int>(0, 0), 1000);
  cv::Mat rgb(3, 3, CV_8UC3, cv::Scalar(1, 2, 3));
  writeRawImage(dir / "rgb.png", rgb);
  EXPECT_TRUE(contains(inputErrorOf([&] { readLabelImage(dir / "rgb.png"); }), "single-channel"));
  EXPECT_TRUE(contains(inputErrorOf([&] { readImage(dir / "missing.png"); }), "missing.png: image file not found"));
  writeText(dir / "junk.png", "not a png");
  EXPECT_TRUE(contains(inputErrorOf([&] { readImage(dir / "junk.png"); }), "junk.png"));
}

TEST(Io_Image, writes_are_atomic_and_leave_no_temporaries) {
  TempDir dir;
  writeImage(dir / "a.png", cv::Mat(2, 2, CV_32FC3, cv::Scalar(0.5, 0.5, 0.5)));
  int files = 0;
  for (auto& e : fs::directory_iterator(dir.path())) {
    ++files;
    EXPECT_EQ(e.path().filename(), "a.png");
  }
  EXPECT_EQ(files, 1);
  EXPECT_THROW(writeImage(dir / "bad.xyz", cv::Mat(2, 2, CV_32FC3)), Exception);
  EXPECT_FALSE(fs::exists(dir / "bad.xyz"));
}

TEST(Io_Obj, parts_uvs_normals_and_triangulation) {
  TempDir dir;
  writeText(dir / "m.obj",
            "# test\nmtllib missing.mtl\n"
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
            "vt 0 0\nvt 2 0\nvt 2 2\nvt 0 2\nvn 0 0 2\n"
            "f 1/1/1 2/2/1 3/3/1\n"           // no usemtl: part "default"
            "usemtl floor\n"
            "f 1/1/1 2/2/1 3/3/1 4/4/1\n"     // quad -> 2 triangles
            "usemtl wall\n"
            "f -4/-4 -3/-3 -2/-2\n"           // relative indices, no normals
            "usemtl floor\n"
            "f 1 3 4\n");
  const ObjMesh m = readObj(dir / "m.obj");
  ASSERT_EQ(m.triangles.size(), 5u);
  ASSERT_EQ(m.materialNames, (std::vector<std::string>{"default", "floor", "wall"}));
  EXPECT_EQ(m.triangleMaterial, (std::vector<int>{0, 1, 1, 2, 1}));
  EXPECT_EQ(m.polygonsTriangulated, 1);
  EXPECT_EQ(m.triangles[3][0].position, 0);
  EXPECT_EQ(m.triangles[3][2].texcoord, 2);
  EXPECT_EQ(m.triangles[3][0].normal, -1);
  EXPECT_EQ(m.triangles[4][1].texcoord, -1);
  EXPECT_FLOAT_EQ(m.texcoords[1].x(), 2.0f);
  EXPECT_FLOAT_EQ(m.normals[0].z(), 1.0f);  // normalized
  EXPECT_EQ(m.triangleLine[3], 16);
  // the quad's two triangles cover it: their areas sum to 1
  float area = 0;
  for (int t : {1, 2}) {
    const auto& tri = m.triangles[t];
    area += 0.5f * (m.positions[tri[1].position] - m.positions[tri[0].position])
                       .cross(m.positions[tri[2].position] - m.positions[tri[0].position])
                       .norm();
  }
  EXPECT_NEAR(area, 1.0f, 1e-6);
}

TEST(Io_Obj, concave_polygon_is_triangulated_inside) {
  TempDir dir;
  // an L-shaped hexagon (area 3)
  writeText(dir / "l.obj", "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\nv 1 2 0\nv 0 2 0\nf 1 2 3 4 5 6\n");
  const ObjMesh m = readObj(dir / "l.obj");
  ASSERT_EQ(m.triangles.size(), 4u);
  float area = 0;
  for (const auto& tri : m.triangles) {
    const Vec3f n = (m.positions[tri[1].position] - m.positions[tri[0].position])
                        .cross(m.positions[tri[2].position] - m.positions[tri[0].position]);
    EXPECT_GT(n.z(), 0.0f);  // same winding as the polygon
    area += 0.5f * n.norm();
  }
  EXPECT_NEAR(area, 3.0f, 1e-5);
}

TEST(Io_Obj, round_trip_through_writer) {
  TempDir dir;
  ObjMesh m;
  m.positions = {Vec3f(0, 0, 0), Vec3f(1, 0, 0), Vec3f(0, 1, 0)};
  m.texcoords = {Vec2f(0, 0), Vec2f(1, 0), Vec2f(0, 1)};
  m.triangles = {{ObjCorner{0, 0, -1}, ObjCorner{1, 1, -1}, ObjCorner{2, 2, -1}}};
  m.triangleMaterial = {0};
  m.materialNames = {"sofa_fabric"};
  writeObj(dir / "w.obj", m);
  const ObjMesh r = readObj(dir / "w.obj");
  EXPECT_EQ(r.materialNames[0], "sofa_fabric");
  EXPECT_FLOAT_EQ(r.texcoords[2].y(), 1.0f);
  EXPECT_EQ(r.triangles[0][1].texcoord, 1);
}

// Objects (the pieces a pose is fitted for): `o` names, else `g` names; the writer keeps them.
TEST(Io_Obj, objects_are_the_o_names_else_the_g_names_and_survive_the_writer) {
  TempDir dir;
  const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  writeTextFile(dir / "o.obj", tri + "o chair_1\ng seat\nusemtl wood\nf 1 2 3\n" +
                                   "o  sofa \nusemtl fabric\nf 1 3 2\nf 2 3 1\n");
  const ObjMesh o = readObj(dir / "o.obj");
  ASSERT_EQ(o.objectNames, (std::vector<std::string>{"chair_1", "sofa"}));
  EXPECT_EQ(o.triangleObject, (std::vector<int>{0, 1, 1}));
  writeTextFile(dir / "g.obj", "f 1 2 3\n" + tri + "g table\nf 1 2 3\n");  // a face before any
  const ObjMesh g = readObj(dir / "g.obj");
  EXPECT_EQ(g.objectNames, (std::vector<std::string>{"table"}));
  EXPECT_EQ(g.triangleObject, (std::vector<int>{-1, 0}));
  writeObj(dir / "w.obj", o);
  const ObjMesh r = readObj(dir / "w.obj");
  EXPECT_EQ(r.objectNames, o.objectNames);
  EXPECT_EQ(r.triangleObject, o.triangleObject);
  EXPECT_EQ(r.triangleMaterial, o.triangleMaterial);
}

// Issue 9, resource limits: refused at the first triangle / vertex over the limit (named by its
// line), and by the file size before anything is read.
TEST(Io_Obj, files_over_the_limits_are_refused_naming_the_line_and_the_limit) {
  TempDir dir;
  writeText(dir / "quads.obj",
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\nf 1 2 3 4\nf 1 2 3\n");
  ObjLimits limits;
  limits.maxTriangles = 5;  // 2 quads (2 triangles each) and a triangle: exactly at the limit
  EXPECT_EQ(readObj(dir / "quads.obj", limits).triangles.size(), 5u);
  limits.maxTriangles = 3;  // the second quad's second triangle is the 4th
  std::string msg = inputErrorOf([&] { readObj(dir / "quads.obj", limits); });
  EXPECT_TRUE(contains(msg, "quads.obj: line 6: expected at most 3 triangles")) << msg;
  limits = ObjLimits();
  limits.maxVertices = 3;
  msg = inputErrorOf([&] { readObj(dir / "quads.obj", limits); });
  EXPECT_TRUE(contains(msg, "quads.obj: line 4: expected at most 3 vertices")) << msg;
  limits = ObjLimits();
  limits.maxFileBytes = 10;
  msg = inputErrorOf([&] { readObj(dir / "quads.obj", limits); });
  EXPECT_TRUE(contains(msg, "quads.obj: expected an OBJ of at most")) << msg;
  EXPECT_TRUE(contains(msg, "but the file is 60 bytes (not read)")) << msg;
  // the defaults: what the README states
  EXPECT_EQ(ObjLimits().maxTriangles, 5'000'000);
  EXPECT_EQ(ObjLimits().maxVertices, 5'000'000);
  EXPECT_EQ(ObjLimits().maxFileBytes, int64_t(1) << 30);
}

TEST(Io_Obj, bad_files_name_the_file_and_line) {
  struct Case {
    const char* file;
    const char* text;  // nullptr: the file is not there
    const char* says;
  };
  const Case cases[] = {
      {"range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9\n",
       "range.obj: line 5: face refers to vertex 9"},
      {"zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "zero.obj: line 4"},
      {"empty.obj", "# nothing\nv 0 0 0\n", "empty.obj: no faces"},
      {"vt.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/2 3/1\n",
       "line 5: face refers to texture coordinate 2"},
      {"two.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n", "line 3: a face needs at least 3 corners"},
      {"nope.obj", nullptr, "nope.obj: OBJ file not found"},
  };
  TempDir dir;
  for (const Case& c : cases) {
    if (c.text) writeText(dir / c.file, c.text);
    const std::string msg = inputErrorOf([&] { readObj(dir / c.file); });
    EXPECT_TRUE(contains(msg, c.says)) << msg;
  }
}

const char* kScene = R"({
  "version": 1,
  "geometry": "room.obj",
  "views": [{
    "image": "photos/view0.png",
    "camera": {"width": 64, "height": 48, "fx": 50, "fy": 50, "cx": 31.5, "cy": 23.5,
               "world_to_camera": [[1,0,0,0],[0,-1,0,1.5],[0,0,-1,3.0],[0,0,0,1]]},
    "segments": "segments/view0.png",
    "segment_parts": {"3": "floor"}
  }, {
    "image": "photos/view1.exr",
    "camera": {"width": 64, "height": 48, "position": [0, 1, 3], "look_at": [0, 1, 0], "up": [0, 1, 0], "fov_y_deg": 60}
  }],
  "lights": {
    "area": [{"part": "lamp"}, {"center": [0, 2.69, 0], "edge_u": [0.4, 0, 0], "edge_v": [0, 0, 0.4], "radiance": [1, 2, 3]}],
    "auto_ceiling_spacing": 2.5,
    "environment": {"image": "sky.hdr", "window_parts": ["window"], "strength": 0.7}
  },
  "parts": {"floor": {"graph": "wood_planks", "category": "wood"},
            "tv": {"fixed": {"albedo": [0.02, 0.02, 0.02], "roughness": 0.15}},
            "painting": {"skip": true}},
  "options": {"preset": "fast", "seed": 7}
})";

TEST(Io_SceneJson, reads_every_key_of_the_spec) {
  TempDir dir;
  writeText(dir / "scene.json", kScene);
  const SceneDesc s = readSceneJson(dir / "scene.json");
  EXPECT_EQ(s.geometry, dir / "room.obj");
  ASSERT_EQ(s.views.size(), 2u);
  EXPECT_EQ(s.views[0].image, dir / "photos/view0.png");
  EXPECT_EQ(s.views[0].segmentParts.at(3), "floor");
  EXPECT_DOUBLE_EQ(s.views[0].camera.fx, 50);
  EXPECT_DOUBLE_EQ(s.views[0].camera.worldToCamera(2, 3), 3.0);
  ASSERT_EQ(s.lights.area.size(), 2u);
  EXPECT_EQ(*s.lights.area[0].part, "lamp");
  EXPECT_DOUBLE_EQ(s.lights.area[1].radiance->z(), 3);
  EXPECT_DOUBLE_EQ(s.lights.autoCeilingSpacing, 2.5);
  EXPECT_EQ(s.lights.environment->windowParts[0], "window");
  EXPECT_DOUBLE_EQ(s.lights.environment->radiance.x(), 0.7);
  EXPECT_EQ(*s.parts.at("floor").graph, "wood_planks");
  EXPECT_EQ(*s.parts.at("floor").category, "wood");
  EXPECT_FALSE(s.parts.at("tv").category.has_value());
  EXPECT_DOUBLE_EQ(s.parts.at("tv").fixed->roughness, 0.15);
  EXPECT_TRUE(s.parts.at("painting").skip);
  EXPECT_EQ(s.options.preset, "fast");
  EXPECT_EQ(s.options.seed, 7u);
}

TEST(Io_SceneJson, look_at_camera_matches_the_explicit_form) {
  TempDir dir;
  writeText(dir / "scene.json", kScene);
  const CameraDesc c = readSceneJson(dir / "scene.json").views[1].camera;
  // camera at (0,1,3) looking down -z with +y up: x right = +x, y down = -y, z forward = -z
  Mat4d expected;
  expected << 1, 0, 0, 0, 0, -1, 0, 1, 0, 0, -1, 3, 0, 0, 0, 1;
  EXPECT_LT((c.worldToCamera - expected).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_NEAR(c.fy, 24.0 / std::tan(kPiD / 6), 1e-9);
  EXPECT_DOUBLE_EQ(c.cx, 31.5);
  EXPECT_DOUBLE_EQ(c.cy, 23.5);
}

struct BadCase {
  const char* name;
  std::string from, to;  // textual substitution in kScene
  std::string expected;  // substring of the message
};

TEST(Io_SceneJson, bad_input_names_file_key_and_expectation) {
  const std::vector<BadCase> cases = {
      {"syntax", "\"version\": 1,", "\"version\": 1,,", "scene.json: line 2, column 16: JSON syntax error"},
      {"type", "\"fx\": 50", "\"fx\": \"50\"", "views[0].camera.fx: expected a number, got string"},
      {"missing", "\"geometry\": \"room.obj\",", "", "geometry: missing required key"},
      {"nan-literal", "\"cx\": 31.5", "\"cx\": NaN", "JSON syntax error"},
      {"inf", "[0,-1,0,1.5]", "[0,-1,0,1e999]", "scene.json: line 7, column 54: JSON number overflow"},
      {"non-rigid", "[0,-1,0,1.5]", "[0,-2,0,1.5]", "views[0].camera.world_to_camera: expected a rigid transform"},
      {"reflection", "[0,0,-1,3.0]", "[0,0,1,3.0]", "expected a rigid transform"},
      {"no views", "\"views\": [{", "\"views\": [], \"x\": [{", "views: expected at least one view"},
      {"segment key", "{\"3\": \"floor\"}", "{\"three\": \"floor\"}", "segment_parts.three: expected a region value"},
      {"preset", "\"fast\"", "\"fastest\"", "options.preset: expected \"fast\", \"balanced\" or \"paper\""},
      {"refine_poses", "\"seed\": 7", "\"seed\": 7, \"refine_poses\": \"yes\"", "options.refine_poses: expected"},
      {"albedo range", "[0.02, 0.02, 0.02]", "[2, 0.02, 0.02]", "parts.tv.fixed.albedo: expected three numbers in [0, 1]"},
      {"light", "{\"part\": \"lamp\"}", "{\"lamp\": 1}", "lights.area[0]: expected \"part\""},
      {"fov", "\"fov_y_deg\": 60", "\"fov_y_deg\": 0", "views[1].camera.fov_y_deg: expected a vertical field of view"},
      {"width", "\"width\": 64, \"height\": 48, \"fx\"", "\"width\": -64, \"height\": 48, \"fx\"", "views[0].camera.width: expected an integer in [1"},
  };
  for (const auto& c : cases) {
    TempDir dir;
    std::string text = kScene;
    const auto pos = text.find(c.from);
    ASSERT_NE(pos, std::string::npos) << c.name;
    text.replace(pos, c.from.size(), c.to);
    writeText(dir / "scene.json", text);
    const std::string msg = inputErrorOf([&] { readSceneJson(dir / "scene.json"); });
    EXPECT_TRUE(contains(msg, c.expected)) << c.name << ": " << msg;
    EXPECT_TRUE(contains(msg, "scene.json")) << c.name << ": " << msg;
  }
  TempDir dir;
  EXPECT_TRUE(contains(inputErrorOf([&] { readSceneJson(dir / "none.json"); }), "none.json: file not found"));
}

TEST(Io_LightsAndMaterials, write_then_read_back) {
  TempDir dir;
  LightsFileDesc lights;
  AreaLightDesc rect;
  rect.name = "ceiling_0";
  rect.center = Vec3d(1.5, 2.69, 1);
  rect.edgeU = Vec3d(0.3, 0, 0);
  rect.edgeV = Vec3d(0, 0, 0.3);
  rect.radiance = Vec3d(12, 11.5, 10.8);
  AreaLightDesc part;
  part.name = "lamp";
  part.part = "lamp_bulb";
  part.radiance = Vec3d(30, 28, 25);
  lights.emitters = {rect, part};
  EnvironmentDesc env;
  env.radiance = Vec3d(0.8, 0.9, 1.0);
  env.windowParts = {"window"};
  lights.environment = env;
  lights.exposure = {1.0, 0.8};
  writeLightsJson(dir / "lights.json", lights);
  const LightsFileDesc r = readLightsJson(dir / "lights.json");
  ASSERT_EQ(r.emitters.size(), 2u);
  EXPECT_EQ(r.emitters[0].name, "ceiling_0");
  EXPECT_DOUBLE_EQ(r.emitters[0].edgeV.z(), 0.3);
  EXPECT_EQ(*r.emitters[1].part, "lamp_bulb");
  EXPECT_DOUBLE_EQ(r.emitters[1].radiance->y(), 28);
  EXPECT_DOUBLE_EQ(r.exposure[1], 0.8);

  fs::create_directories(dir / "out/materials");
  MaterialFileDesc m;
  m.part = "floor";
  m.graph = "wood_planks";
  m.category = "wood";
  m.params = {{"plank_width", 0.18}};
  m.uv.rotationDeg = 90;
  m.uv.scale = Vec2d(1.5, 1.5);
  m.uv.offset = Vec2d(0.1, 0);
  m.maps["albedo"] = dir / "out/textures/floor_albedo.png";
  m.fitView = 0;
  m.fitLoss = 0.012;
  writeMaterialJson(dir / "out/materials/floor.json", m, dir / "out");
  const std::string text = readTextFile(dir / "out/materials/floor.json");
  EXPECT_TRUE(contains(text, "\"textures/floor_albedo.png\"")) << text;
  const MaterialFileDesc back = readMaterialJson(dir / "out/materials/floor.json");
  EXPECT_EQ(back.maps.at("albedo"), dir / "out/textures/floor_albedo.png");
  EXPECT_DOUBLE_EQ(back.uv.scale.x(), 1.5);
  EXPECT_DOUBLE_EQ(back.uv.rotationDeg, 90);
  EXPECT_DOUBLE_EQ(*back.fitLoss, 0.012);
  EXPECT_FALSE(back.skipped.has_value());
}

TEST(Io_SharedData, reads_the_example_cases_when_present) {
  const fs::path room = fs::path(PS_SHARED_DATA_DIR) / "examples/blender-room";
  if (!fs::exists(room / "scene.json")) GTEST_SKIP() << "shared data not present";
  const SceneDesc s = readSceneJson(room / "scene.json");
  EXPECT_EQ(s.views.size(), 1u);
  const ObjMesh m = readObj(s.geometry);
  EXPECT_EQ(m.triangles.size(), 12616u);
  EXPECT_NE(std::find(m.materialNames.begin(), m.materialNames.end(), "sofa_dark_fabric"), m.materialNames.end());
  const cv::Mat photo = readImage(s.views[0].image);
  EXPECT_EQ(photo.cols, 640);
  const cv::Mat seg = readLabelImage(*s.views[0].segments);
  double maxv;
  cv::minMaxLoc(seg, nullptr, &maxv);
  EXPECT_GE(maxv, 1000);
  const MaterialFileDesc floor = readMaterialJson(room / "gt/twin/materials/floor.json");
  EXPECT_DOUBLE_EQ(floor.uv.rotationDeg, 90);
  EXPECT_TRUE(fs::exists(floor.maps.at("albedo")));
  const LightsFileDesc lights = readLightsJson(room / "gt/twin/lights.json");
  EXPECT_EQ(lights.emitters.size(), 2u);
  EXPECT_TRUE(fs::exists(*lights.environment->image));
}

}  // namespace
}  // namespace ps::io
