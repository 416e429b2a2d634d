#include <gtest/gtest.h>

#include <fstream>
#include <opencv2/calib3d.hpp>

#include "photoscene/core.hpp"
#include "photoscene/io.hpp"
#include "photoscene/scene.hpp"
// the bad-input helpers of the io tests (test-only code, shared rather than copied)
#include "../../io/test/input_error_of.hpp"

namespace ps {
namespace {

using io::TempDir;

using test::contains;
using test::inputErrorOf;

Mat4d lookAt(const Vec3d& eye, const Vec3d& target, const Vec3d& up) {
  return io::lookAtWorldToCamera(eye, target, up);
}

TEST(Scene_Camera, projects_like_opencv_projectPoints) {
  Rng rng(5);
  for (int trial = 0; trial < 20; ++trial) {
    const Vec3d eye(rng.uniform(-2, 2), rng.uniform(0.5, 2), rng.uniform(-2, 2));
    const Vec3d target(rng.uniform(-1, 1), rng.uniform(0, 1), rng.uniform(-1, 1));
    const Camera cam(640, 480, rng.uniform(300, 700), rng.uniform(300, 700), rng.uniform(300, 340),
                     rng.uniform(220, 260), lookAt(eye, target + Vec3d(0, 0, 3), Vec3d(0, 1, 0)));
    std::vector<cv::Point3d> pts;
    for (int i = 0; i < 50; ++i) {
      const Vec3d p = cam.unproject(Vec2d(rng.uniform(0, 640), rng.uniform(0, 480)), rng.uniform(0.5, 8));
      pts.emplace_back(p.x(), p.y(), p.z());
    }
    cv::Mat R(3, 3, CV_64F), t(3, 1, CV_64F);
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) R.at<double>(r, c) = cam.worldToCamera()(r, c);
      t.at<double>(r) = cam.worldToCamera()(r, 3);
    }
    cv::Mat rvec;
    cv::Rodrigues(R, rvec);
    const cv::Matx33d K(cam.fx(), 0, cam.cx(), 0, cam.fy(), cam.cy(), 0, 0, 1);
    std::vector<cv::Point2d> ref;
    cv::projectPoints(pts, rvec, t, K, cv::noArray(), ref);
    for (size_t i = 0; i < pts.size(); ++i) {
      Vec2d px;
      ASSERT_TRUE(cam.project(Vec3d(pts[i].x, pts[i].y, pts[i].z), &px));
      EXPECT_NEAR(px.x(), ref[i].x, 1e-4);
      EXPECT_NEAR(px.y(), ref[i].y, 1e-4);
    }
  }
}

TEST(Scene_Camera, unproject_and_rays_invert_projection) {
  const Camera cam(320, 240, 250, 260, 159.5, 119.5, lookAt(Vec3d(1, 1.5, 2), Vec3d(0, 1, 0), Vec3d(0, 1, 0)));
  const Vec2d px(37.25, 201.5);
  const Vec3d p = cam.unproject(px, 3.5);
  Vec2d back;
  double depth = 0;
  ASSERT_TRUE(cam.project(p, &back, &depth));
  EXPECT_NEAR((back - px).norm(), 0, 1e-9);
  EXPECT_NEAR(depth, 3.5, 1e-9);
  const Vec3d dir = cam.rayDirection(px.x(), px.y());
  EXPECT_NEAR(dir.norm(), 1, 1e-12);
  EXPECT_NEAR((p - cam.position()).normalized().dot(dir), 1, 1e-12);
  EXPECT_FALSE(cam.project(cam.position() - dir, &back));  // behind the camera
  // pixel center (0, 0) stays on the same ray after resizing by 2
  const Camera half = cam.resized(160, 120);
  Vec2d h;
  ASSERT_TRUE(half.project(p, &h));
  EXPECT_NEAR((h.x() + 0.5) * 2, px.x() + 0.5, 1e-9);
  EXPECT_NEAR((h.y() + 0.5) * 2, px.y() + 0.5, 1e-9);
}

/// An axis-aligned box room [x0,x1] x [0,h] x [z0,z1] with inward-facing parts.
io::ObjMesh boxRoom(float x0, float x1, float h, float z0, float z1, bool withUvs) {
  io::ObjMesh m;
  m.materialNames = {"floor", "ceiling", "wall_a", "wall_b", "wall_c", "wall_d"};
  auto quad = [&](Vec3f a, Vec3f b, Vec3f c, Vec3f d, int mat) {
    const int base = static_cast<int>(m.positions.size());
    for (auto& p : {a, b, c, d}) m.positions.push_back(p);
    const int tb = static_cast<int>(m.texcoords.size());
    if (withUvs) {
      m.texcoords.push_back(Vec2f(0, 0));
      m.texcoords.push_back(Vec2f((b - a).norm(), 0));
      m.texcoords.push_back(Vec2f((b - a).norm(), (c - b).norm()));
      m.texcoords.push_back(Vec2f(0, (c - b).norm()));
    }
    auto corner = [&](int k) { return io::ObjCorner{base + k, withUvs ? tb + k : -1, -1}; };
    m.triangles.push_back({corner(0), corner(1), corner(2)});
    m.triangles.push_back({corner(0), corner(2), corner(3)});
    m.triangleMaterial.push_back(mat);
    m.triangleMaterial.push_back(mat);
  };
  // counter-clockwise seen from inside
  quad({x0, 0, z1}, {x1, 0, z1}, {x1, 0, z0}, {x0, 0, z0}, 0);  // floor, normal +y
  quad({x0, h, z0}, {x1, h, z0}, {x1, h, z1}, {x0, h, z1}, 1);  // ceiling, -y
  quad({x0, 0, z0}, {x1, 0, z0}, {x1, h, z0}, {x0, h, z0}, 2);  // z0 wall, +z
  quad({x1, 0, z1}, {x0, 0, z1}, {x0, h, z1}, {x1, h, z1}, 3);  // z1 wall, -z
  quad({x1, 0, z0}, {x1, 0, z1}, {x1, h, z1}, {x1, h, z0}, 4);  // x1 wall, -x
  quad({x0, 0, z1}, {x0, 0, z0}, {x0, h, z0}, {x0, h, z1}, 5);  // x0 wall, +x
  m.triangleLine.assign(m.triangles.size(), 0);
  return m;
}

TEST(Scene_Mesh, box_room_normals_face_inward) {
  std::vector<Part> parts;
  const Mesh mesh = meshFromObj(boxRoom(-3, 3, 2.7f, -2, 2, true), &parts, Vec3f(0, 1, 0));
  ASSERT_EQ(parts.size(), 6u);
  EXPECT_EQ(parts[0].name, "floor");
  EXPECT_EQ(parts[0].triangleCount, 2);
  EXPECT_GT(mesh.faceNormal(0).y(), 0.99f);
  EXPECT_LT(mesh.faceNormal(2).y(), -0.99f);
  EXPECT_GT(mesh.faceNormal(4).z(), 0.99f);
  EXPECT_NEAR(mesh.area(0) + mesh.area(1), 24.0f, 1e-4);
}

TEST(Scene_Lights, auto_ceiling_grid_in_a_6_by_4_room_is_2_by_2_centered) {
  std::vector<Part> parts;
  const Mesh mesh = meshFromObj(boxRoom(-3, 3, 2.7f, -2, 2, true), &parts, Vec3f(0, 1, 0));
  const auto lights = autoCeilingLights(mesh, Vec3f(0, 1, 0), 3.0f);
  ASSERT_EQ(lights.size(), 4u);
  Vec3f mean = Vec3f::Zero();
  std::vector<float> xs, zs;
  for (const auto& l : lights) {
    mean += l.center / 4;
    EXPECT_NEAR(l.center.y(), 2.69f, 1e-4);
    EXPECT_LT(l.normal().y(), -0.999f);  // facing down
    EXPECT_GT(l.rectangleArea(), 0.0f);
    EXPECT_TRUE(l.automatic);
    xs.push_back(std::abs(l.center.x()));
    zs.push_back(std::abs(l.center.z()));
  }
  EXPECT_NEAR(mean.x(), 0, 1e-5);
  EXPECT_NEAR(mean.z(), 0, 1e-5);
  for (float x : xs) EXPECT_NEAR(x, 1.5f, 1e-5);  // centers of the two 3 m cells
  for (float z : zs) EXPECT_NEAR(z, 1.0f, 1e-5);  // centers of the two 2 m cells
  EXPECT_EQ(autoCeilingLights(mesh, Vec3f(0, 1, 0), 10.0f).size(), 1u);
  EXPECT_EQ(autoCeilingLights(mesh, Vec3f(0, 1, 0), 1.0f).size(), 24u);
}

TEST(Scene_Lights, auto_ceiling_follows_another_up_axis) {
  io::ObjMesh obj = boxRoom(-3, 3, 2.7f, -2, 2, true);
  for (auto& p : obj.positions) p = Vec3f(p.x(), -p.z(), p.y());  // y up -> z up
  std::vector<Part> parts;
  const Mesh mesh = meshFromObj(obj, &parts, Vec3f(0, 0, 1));
  const auto lights = autoCeilingLights(mesh, Vec3f(0, 0, 1), 3.0f);
  ASSERT_EQ(lights.size(), 4u);
  for (const auto& l : lights) {
    EXPECT_NEAR(l.center.z(), 2.69f, 1e-4);
    EXPECT_LT(l.normal().z(), -0.999f);
  }
}

TEST(Scene_Mesh, generated_uvs_are_metric_and_cover_every_triangle) {
  std::vector<Part> parts;
  const Mesh mesh = meshFromObj(boxRoom(-3, 3, 2.7f, -2, 2, false), &parts, Vec3f(0, 1, 0));
  for (const Part& p : parts) EXPECT_EQ(p.generatedUvTriangles, 2) << p.name;
  for (size_t t = 0; t < mesh.numTriangles(); ++t) {
    EXPECT_TRUE(mesh.generatedUv[t]);
    // planar projection of a planar face: UV distances equal 3D distances (meters)
    for (int a = 0; a < 3; ++a) {
      const int b = (a + 1) % 3;
      const float d3 = (mesh.positions[mesh.triangles[t][a]] - mesh.positions[mesh.triangles[t][b]]).norm();
      const float d2 = (mesh.cornerUvs[3 * t + a] - mesh.cornerUvs[3 * t + b]).norm();
      EXPECT_NEAR(d2, d3, 1e-4) << "triangle " << t;
    }
    // same orientation as the face (no mirroring): UV winding positive seen along the normal
    const Vec2f e1 = mesh.cornerUvs[3 * t + 1] - mesh.cornerUvs[3 * t];
    const Vec2f e2 = mesh.cornerUvs[3 * t + 2] - mesh.cornerUvs[3 * t];
    EXPECT_GT(e1.x() * e2.y() - e1.y() * e2.x(), 0.0f) << "triangle " << t;
  }
  // walls: v grows upward
  const int wall = 4;  // first triangle of wall_a
  for (int k = 0; k < 3; ++k) {
    const Vec3f& p = mesh.positions[mesh.triangles[wall][k]];
    EXPECT_NEAR(mesh.cornerUvs[3 * wall + k].y(), p.y(), 1e-5);
  }
}

TEST(Scene_Lights, environment_mapping_follows_the_contract) {
  EnvironmentLight env;
  env.image = cv::Mat(16, 32, CV_32FC3, cv::Scalar(1, 1, 1));
  env.image(cv::Rect(0, 0, 32, 8)).setTo(cv::Scalar(2, 2, 2));  // upper half brighter
  EXPECT_NEAR(env.directionToUv(Vec3f(1, 0, 0)).x(), 0.5f, 1e-6);
  EXPECT_NEAR(env.directionToUv(Vec3f(1, 0, 0)).y(), 0.5f, 1e-6);
  EXPECT_NEAR(env.directionToUv(Vec3f(0, 1, 0)).y(), 0.0f, 1e-6);
  EXPECT_NEAR(env.directionToUv(Vec3f(0, 0, 1)).x(), 0.75f, 1e-6);
  EXPECT_NEAR(env.directionToUv(Vec3f(-1, 0, -1e-6f)).x(), 0.0f, 1e-5);
  env.rotationDeg = 90;
  EXPECT_NEAR(env.directionToUv(Vec3f(0, 0, 1)).x(), 0.5f, 1e-6);
  Rng rng(2);
  for (int i = 0; i < 100; ++i) {
    const Vec3f d = Vec3f(rng.normal(), rng.normal(), rng.normal()).normalized();
    EXPECT_NEAR((env.uvToDirection(env.directionToUv(d)) - d).norm(), 0, 1e-4);
  }
  EXPECT_NEAR(env.radianceFrom(Vec3f(0, 1, 0)).x(), 2.0f, 1e-5);
  EXPECT_NEAR(env.radianceFrom(Vec3f(0, -1, 0)).x(), 1.0f, 1e-5);
}

/// Writes a loadable scene: a 6 x 2.7 x 4 m box room, a 64 x 48 photo, a label image.
struct TestScene {
  TempDir dir;
  nlohmann::json json;
  TestScene() {
    io::writeObj(dir / "room.obj", boxRoom(-3, 3, 2.7f, -2, 2, true));
    fs::create_directories(dir / "photos");
    io::writeImage(dir / "photos/view0.png", cv::Mat(48, 64, CV_32FC3, cv::Scalar(0.3, 0.3, 0.3)));
    cv::Mat labels(48, 64, CV_16UC1, cv::Scalar(1));
    labels(cv::Rect(0, 30, 64, 18)).setTo(2);
    io::writeRawImage(dir / "labels.png", labels);
    const Mat4d w2c = lookAt(Vec3d(0, 1.5, 1.5), Vec3d(0, 1.2, -2), Vec3d(0, 1, 0));
    io::CameraDesc cam{64, 48, 50, 50, 31.5, 23.5, w2c};
    json = {{"version", 1},
            {"geometry", "room.obj"},
            {"views",
             {{{"image", "photos/view0.png"},
               {"camera", io::cameraToJson(cam)},
               {"segments", "labels.png"},
               {"segment_parts", {{"1", "wall_a"}, {"2", "floor"}}}}}},
            {"parts", {{"ceiling", {{"skip", true}}}}}};
  }
  fs::path write() {
    io::writeJsonFile(dir / "scene.json", json);
    return dir / "scene.json";
  }
};

TEST(Scene_Load, loads_a_consistent_scene) {
  TestScene t;
  const Scene s = loadScene(t.write());
  EXPECT_EQ(s.parts.size(), 6u);
  ASSERT_EQ(s.views.size(), 1u);
  EXPECT_EQ(s.views[0].photo.type(), CV_32FC3);
  EXPECT_EQ(s.views[0].segments.type(), CV_32SC1);
  EXPECT_EQ(s.views[0].segmentParts.at(2), s.partId("floor"));
  EXPECT_EQ(s.lights.area.size(), 4u);  // automatic 3 m grid on a 6 x 4 m room
  EXPECT_GT(countTrianglesInFrustum(s.mesh, s.views[0].camera), 0);
}

TEST(Scene_Load, bad_input_is_refused_with_file_key_and_expectation) {
  struct Case {
    const char* name;
    std::function<void(TestScene&)> edit;
    std::string expected;
  };
  const std::vector<Case> cases = {
      {"photo size", [](TestScene& t) { t.json["views"][0]["camera"]["width"] = 65; },
       "views[0].image: expected a 65x48 image (the camera's width x height)"},
      {"segments size",
       [](TestScene& t) { io::writeRawImage(t.dir / "labels.png", cv::Mat(10, 10, CV_16UC1, cv::Scalar(1))); },
       "views[0].segments: expected a label image of the photo's size 64x48"},
      {"segment part", [](TestScene& t) { t.json["views"][0]["segment_parts"]["2"] = "flor"; },
       "views[0].segment_parts.2: unknown part \"flor\""},
      {"parts", [](TestScene& t) { t.json["parts"]["sofa"] = {{"skip", true}}; }, "parts.sofa: unknown part \"sofa\""},
      {"light part", [](TestScene& t) { t.json["lights"] = {{"area", {{{"part", "lamp"}}}}}; },
       "lights.area[0].part: unknown part \"lamp\""},
      {"window", [](TestScene& t) { t.json["lights"] = {{"environment", {{"window_parts", {"glass"}}}}}; },
       "lights.environment.window_parts[0]: unknown part \"glass\""},
      {"missing photo", [](TestScene& t) { t.json["views"][0]["image"] = "photos/nope.png"; },
       "nope.png: image file not found"},
      {"invisible", [](TestScene& t) {
         t.json["views"][0]["camera"] = io::cameraToJson(io::CameraDesc{
             64, 48, 50, 50, 31.5, 23.5, lookAt(Vec3d(0, 1.5, 50), Vec3d(0, 1.5, 100), Vec3d(0, 1, 0))});
       }, "room.obj: no triangle is visible from any view"},
  };
  for (const auto& c : cases) {
    TestScene t;
    c.edit(t);
    const std::string msg = inputErrorOf([&] { loadScene(t.write()); });
    EXPECT_TRUE(contains(msg, c.expected)) << c.name << ": " << msg;
  }
}

TEST(Scene_Load, blender_room_example_when_present) {
  const fs::path room = fs::path(PS_SHARED_DATA_DIR) / "examples/blender-room/scene.json";
  if (!fs::exists(room)) GTEST_SKIP() << "shared data not present";
  const Scene s = loadScene(room);
  EXPECT_EQ(s.lights.area.size(), 2u);
  EXPECT_EQ(s.lights.area[0].kind, AreaLight::Kind::Part);
  ASSERT_TRUE(s.lights.environment.has_value());
  EXPECT_FALSE(s.lights.environment->image.empty());
  EXPECT_EQ(s.lights.environment->windowParts.size(), 1u);
  EXPECT_GE(s.parts.size(), 20u);
  // every pinned region of the label image names a part the OBJ has
  for (const auto& [value, part] : s.views[0].segmentParts) EXPECT_GE(part, 0);
  // the emitter parts face down
  const int light0 = s.partId("light_0");
  for (size_t t = 0; t < s.mesh.numTriangles(); ++t) {
    if (s.mesh.partIds[t] == light0) {
      EXPECT_LT(s.mesh.faceNormal(static_cast<int>(t)).y(), -0.99f);
    }
  }
}

TEST(Scene_Load, sunrgbd_example_gets_automatic_ceiling_lights) {
  const fs::path scenePath = fs::path(PS_SHARED_DATA_DIR) / "examples/sunrgbd-128/scene.json";
  if (!fs::exists(scenePath)) GTEST_SKIP() << "shared data not present";
  const Scene s = loadScene(scenePath);
  EXPECT_GE(s.lights.area.size(), 2u);
  for (const auto& l : s.lights.area) EXPECT_TRUE(l.automatic);
}

}  // namespace
}  // namespace ps
