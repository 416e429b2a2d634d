// The ps::Light interface of the built-in lights: sampling densities that integrate to the solid
// angle they cover, sampleLi's pdf equal to pdfLi for the same direction, the lights.json round
// trip through the registry, the order of LightSet::all().
#include <gtest/gtest.h>

#include <utility>

#include "photoscene/core.hpp"
#include "photoscene/io.hpp"
#include "photoscene/scene.hpp"

namespace ps {
namespace {

// Every ray is visible (the tests check densities, not shadows).
struct AllVisible final : LightRays {
  bool unoccluded(const Vec3f&, const Vec3f&) const override { return true; }
  bool unoccludedToInfinity(const Vec3f&, const Vec3f&) const override { return true; }
  bool escapesThroughOpenings(const Vec3f&, const Vec3f&, LightEscape*) const override {
    return true;
  }
};

Mesh oneTriangle() {
  Mesh m;
  m.positions = {Vec3f(-1, 0, -1), Vec3f(1, 0, -1), Vec3f(0, 0, 1)};
  m.triangles = {Eigen::Vector3i(0, 1, 2)};
  m.cornerNormals.assign(3, Vec3f(0, 1, 0));
  m.cornerUvs.assign(3, Vec2f::Zero());
  m.partIds = {0};
  m.generatedUv = {0};
  return m;
}

LightSampleContext contextAt(const Vec3f& p, const Vec3f& n, const LightRays& rays) {
  LightSampleContext ctx;
  ctx.p = p;
  ctx.n = n;
  ctx.org = p;
  ctx.selectionPdf = 1;
  ctx.rays = &rays;
  return ctx;
}

// Mean over stratified samples of 1 / pdf (0 where sampling fails): the solid angle the light's
// samples cover, seen from ctx.p. Also checks sampleLi's pdf against pdfLi of the same direction.
double coveredSolidAngle(const Light& light, const LightSampleContext& ctx, int primitive,
                         double* maxPdfError, int n = 256) {
  double sum = 0;
  *maxPdfError = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      LightLiSample s;
      if (!light.sampleLi(ctx, 0.5f, Vec2f((i + 0.5f) / n, (j + 0.5f) / n), &s)) continue;
      sum += 1.0 / s.pdf;
      LightHit hit;
      hit.dir = s.wi;
      hit.t = s.dist;
      hit.primitive = primitive;
      const float p = light.pdfLi(ctx, hit);
      *maxPdfError = std::max(*maxPdfError, std::abs(p - s.pdf) / static_cast<double>(s.pdf));
    }
  return sum / (static_cast<double>(n) * n);
}

TEST(Scene_LightInterface, rectangle_light_density_covers_its_solid_angle) {
  const Mesh mesh = oneTriangle();
  AreaLight rect;
  rect.name = "panel";
  rect.center = Vec3f(0, 2, 0);
  rect.edgeU = Vec3f(1, 0, 0);
  rect.edgeV = Vec3f(0, 0, 0.5f);  // x cross z = -y: emits downwards
  rect.radiance = Vec3f::Ones();
  LightScene ls;
  ls.mesh = &mesh;
  ls.self = 0;
  rect.preprocess(ls);
  const AllVisible rays;
  // near: sampled by solid angle; far: by area. Both cover the rectangle's solid angle, which
  // far away is area x cos / d^2.
  for (const Vec3f& p : {Vec3f(0.2f, 0, 0.1f), Vec3f(0, -400, 0)}) {
    double pdfErr = 0;
    const double omega = coveredSolidAngle(rect, contextAt(p, Vec3f(0, 1, 0), rays), 0, &pdfErr);
    const Vec3f d = rect.center - p;
    const float far = 0.5f * (d.y() / d.norm()) / d.squaredNorm();
    if (p.y() < -100) {
      EXPECT_NEAR(omega, far, 1e-3 * far);
    } else {
      // exact solid angle of the rectangle seen from p (Van Oosterom-Strackee on its 2 triangles)
      auto tri = [&](const Vec3f& a, const Vec3f& b, const Vec3f& c) {
        const Vec3d r1 = (a - p).cast<double>(), r2 = (b - p).cast<double>(),
                    r3 = (c - p).cast<double>();
        const double l1 = r1.norm(), l2 = r2.norm(), l3 = r3.norm();
        const double num = std::abs(r1.dot(r2.cross(r3)));
        const double den = l1 * l2 * l3 + r1.dot(r2) * l3 + r1.dot(r3) * l2 + r2.dot(r3) * l1;
        return 2 * std::atan2(num, den);
      };
      const Vec3f c = rect.center, hu = 0.5f * rect.edgeU, hv = 0.5f * rect.edgeV;
      const double exact =
          tri(c - hu - hv, c + hu - hv, c + hu + hv) + tri(c - hu - hv, c + hu + hv, c - hu + hv);
      EXPECT_NEAR(omega, exact, 1e-3 * exact);
    }
    EXPECT_LT(pdfErr, 1e-4) << "sampleLi's pdf against pdfLi";
  }
  // behind the one-sided emitter nothing is sampled
  double pdfErr = 0;
  EXPECT_EQ(coveredSolidAngle(rect, contextAt(Vec3f(0, 3, 0), Vec3f(0, -1, 0), rays), 0, &pdfErr),
            0.0);
}

TEST(Scene_LightInterface, environment_density_covers_the_hemisphere) {
  const Mesh mesh = oneTriangle();
  const AllVisible rays;
  for (bool withImage : {false, true}) {
    EnvironmentLight env;
    if (withImage) {
      env.image = cv::Mat(16, 32, CV_32FC3);
      cv::randu(env.image, 0.0f, 1.0f);
      env.image.at<cv::Vec3f>(4, 7) = cv::Vec3f(200, 180, 150);  // a sun
    }
    LightScene ls;
    ls.mesh = &mesh;
    env.preprocess(ls);
    double pdfErr = 0;
    // 1024^2 stratified samples: the quadrature error of the peaked image is 3 % at 256^2,
    // 0.2 % here
    const double omega =
        coveredSolidAngle(env, contextAt(Vec3f::Zero(), Vec3f(0, 1, 0), rays), -1, &pdfErr, 1024);
    EXPECT_NEAR(omega, 2 * kPiD, 0.01 * 2 * kPiD) << (withImage ? "image" : "constant");
    EXPECT_LT(pdfErr, 1e-5);
  }
}

TEST(Scene_LightInterface, lights_round_trip_through_the_registry_in_all_order) {
  const fs::path room = fs::path(PS_SHARED_DATA_DIR) / "examples/blender-room/scene.json";
  if (!fs::exists(room)) GTEST_SKIP() << "shared data not present";
  const Scene s = loadScene(room, {false, false});
  const std::vector<const Light*> all = s.lights.all();
  ASSERT_EQ(all.size(), 3u);
  EXPECT_EQ(all[0]->type(), "area");
  EXPECT_EQ(all[2]->type(), "environment");
  EXPECT_EQ(s.lights.environmentIndex(), 2);
  EXPECT_TRUE(all[2]->isInfinite());
  EXPECT_EQ(s.lights.openingParts(), std::vector<int>{s.partId("window")});
  EXPECT_EQ(s.lights.emittingParts(), (std::vector<int>{s.partId("light_0"), s.partId("light_1")}));
  LightJsonContext ctx;
  ctx.parts = &s.parts;
  ctx.baseDir = room.parent_path();
  ctx.file = "memory";
  ctx.loadImages = false;
  for (const Light* l : all) {
    const nlohmann::json j = l->toJson(ctx);
    const auto again = LightRegistry::create(io::JsonValue(j, "memory"), ctx);
    EXPECT_EQ(again->toJson(ctx), j) << l->label();
  }
  const nlohmann::json file = lightsToJson(s.lights, ctx, {1.0});
  EXPECT_EQ(file["emitters"].size(), 2u);
  ASSERT_TRUE(file.contains("environment"));
  EXPECT_FALSE(file["environment"].contains("type"));  // the contract's environment object
  EXPECT_EQ(file["environment"]["window_parts"], nlohmann::json::array({"window"}));
  EXPECT_EQ(file["environment"]["image"], "env/forest.exr");

  // a light set copies its lights: changing the copy leaves the original
  LightSet copy = s.lights;
  copy.all()[0]->setScale(Vec3f(7, 7, 7));
  EXPECT_FALSE(s.lights.area[0].radiance.has_value());
  EXPECT_TRUE(copy.area[0].radiance->isApprox(Vec3f(7, 7, 7)));
}

TEST(Scene_LightInterface, unknown_light_type_is_bad_input_naming_the_key) {
  const Mesh mesh = oneTriangle();
  std::vector<Part> parts(1);
  parts[0].name = "floor";
  parts[0].id = 0;
  io::TempDir dir;
  const fs::path f = dir.path() / "lights.json";
  io::writeJsonFile(f, nlohmann::json::parse(R"({"emitters": [
      {"type": "area", "center": [0, 2, 0], "edge_u": [1, 0, 0], "edge_v": [0, 0, 1], "radiance": [1, 1, 1]},
      {"type": "spot", "position": [0, 2, 0]}]})"));
  const io::LightsFileDesc d = io::readLightsJson(f);
  ASSERT_EQ(d.emitters.size(), 1u);
  ASSERT_EQ(d.registered.size(), 1u);
  try {
    makeLights(d, mesh, parts, Vec3f(0, 1, 0), f.string());
    FAIL() << "an unknown light type was accepted";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(f.string()), std::string::npos) << m;
    EXPECT_NE(m.find("emitters[1].type"), std::string::npos) << m;
    EXPECT_NE(m.find("\"area\""), std::string::npos) << m;
  }
}

}  // namespace
}  // namespace ps

namespace ps {
namespace {

AreaLight rectangleLight(const std::string& name, const Vec3f& center) {
  AreaLight l;
  l.name = name;
  l.center = center;
  l.edgeU = Vec3f(0.5f, 0, 0);
  l.edgeV = Vec3f(0, 0, 0.5f);
  return l;
}

AreaLight partLight(const std::string& name, int part) {
  AreaLight l;
  l.name = name;
  l.kind = AreaLight::Kind::Part;
  l.partId = part;
  return l;
}

TEST(Scene_LightInterface, fitted_lights_are_those_without_a_scale_and_the_environment) {
  LightSet set;
  set.area.push_back(rectangleLight("a", Vec3f(0, 2, 0)));
  set.area.push_back(rectangleLight("b", Vec3f(1, 2, 0)));
  set.area[1].radiance = Vec3f(3, 3, 3);  // given: held
  set.area.push_back(partLight("lamp", 4));
  EXPECT_EQ(set.fittedLights(), (std::vector<int>{0, 2}));
  set.environment = EnvironmentLight();  // its multiplier is always fitted
  EXPECT_EQ(set.fittedLights(), (std::vector<int>{0, 2, 3}));
  EXPECT_EQ(set.emittingParts(), std::vector<int>{4});
}

TEST(Scene_LightInterface, match_light_by_part_then_label_then_nearest_shape) {
  LightSet other;
  other.area.push_back(rectangleLight("far", Vec3f(5, 2, 5)));
  other.area.push_back(rectangleLight("near", Vec3f(0.2f, 2, 0)));
  other.area.push_back(partLight("renamed lamp", 7));
  other.environment = EnvironmentLight();
  const std::vector<const Light*> list = std::as_const(other).all();
  // the same emitting part, whatever the name
  EXPECT_EQ(matchLight(partLight("lamp", 7), list), 2);
  // a part light with no part in common matches nothing (not a rectangle by distance)
  EXPECT_EQ(matchLight(partLight("lamp", 8), list), -1);
  // the same label
  EXPECT_EQ(matchLight(rectangleLight("far", Vec3f(0, 2, 0)), list), 0);
  // the nearest rectangle center within 0.5 m, else none
  EXPECT_EQ(matchLight(rectangleLight("x", Vec3f(0, 2, 0)), list), 1);
  EXPECT_EQ(matchLight(rectangleLight("x", Vec3f(0, 2, 3)), list), -1);
  // infinite lights match their kind
  EXPECT_EQ(matchLight(EnvironmentLight(), list), 3);
}

}  // namespace
}  // namespace ps
