// A light type defined and registered in this file alone -- an isotropic point light -- read
// from a lights.json, written back, and rendered by the path tracer: "a new light type is one
// file plus its registration". The render is checked against the inverse-square law.
#include <gtest/gtest.h>

#include <fstream>

#include "photoscene/io/json.hpp"
#include "test_scenes.hpp"

namespace ps {
namespace {

using namespace ps::test;

// ---- the new light type: everything it takes -------------------------------------------------

/// An isotropic point light: intensity I (W / sr per channel) at `position`.
class PointLight final : public Light {
 public:
  std::string name = "point";
  Vec3f position = Vec3f::Zero();
  std::optional<Vec3f> intensity;  ///< absent: to be fitted

  std::string type() const override { return "point"; }
  std::string label() const override { return name; }
  std::unique_ptr<Light> clone() const override { return std::make_unique<PointLight>(*this); }
  std::optional<Vec3f> scale() const override { return intensity; }
  void setScale(const Vec3f& s) override { intensity = s; }
  bool isDeltaPosition() const override { return true; }
  // the power of unit radiance over 1 m^2 is pi; a point light sends 4 pi I
  float power(const Vec3f& s) const override { return 4 * kPi * luminanceOf(s); }
  bool sampleLi(const LightSampleContext& ctx, float, const Vec2f&,
                LightLiSample* out) const override {
    const Vec3f d = position - ctx.p;
    const float d2 = d.squaredNorm();
    if (!(d2 > 1e-12f)) return false;
    out->dist = std::sqrt(d2);
    out->wi = d / out->dist;
    if (out->wi.dot(ctx.n) <= 0) return false;
    out->L = Vec3f::Constant(1.0f / d2);  // radiance of a delta: I / d^2 per unit intensity
    out->pdf = ctx.selectionPdf;          // a delta in direction: only the selection
    return ctx.rays->unoccluded(ctx.org, position);
  }
  nlohmann::json toJson(const LightJsonContext&) const override {
    const Vec3f i = intensity.value_or(Vec3f::Zero());
    return {{"type", "point"},
            {"name", name},
            {"position", {position.x(), position.y(), position.z()}},
            {"intensity", {i.x(), i.y(), i.z()}}};
  }
  static std::unique_ptr<Light> fromJson(const io::JsonValue& e, const LightJsonContext&) {
    auto l = std::make_unique<PointLight>();
    if (auto n = e.get("name")) l->name = n->string();
    l->position = e["position"].vec3().cast<float>();
    if (auto i = e.get("intensity")) {
      const Vec3d v = i->vec3();
      if ((v.array() < 0).any()) i->fail("three non-negative numbers (W / sr, linear RGB)");
      l->intensity = v.cast<float>();
    }
    return l;
  }
};

PS_REGISTER_LIGHT("point", PointLight::fromJson);

// ---- tests --------------------------------------------------------------------------------------

// A 20 x 20 m Lambertian floor (y = 0, facing up) and nothing else: no surface sees another, so
// what the camera sees is exactly one bounce, L = albedo / pi * I cos(theta) / d^2.
Scene floorScene() {
  Scene s;
  const int part = addPart(s, "floor");
  addQuad(s.mesh, Vec3f(-10, 0, 10), Vec3f(20, 0, 0), Vec3f(0, 0, -20), part);
  return s;
}

std::filesystem::path writeLights(const std::string& name, const std::string& text) {
  const auto dir = std::filesystem::temp_directory_path() / "ps_test_light_registry";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / name) << text;
  return dir / name;
}

TEST(Raytrace_LightRegistry, point_light_registered_in_one_file_is_read_and_written) {
  ASSERT_TRUE(LightRegistry::has("point"));
  ASSERT_TRUE(LightRegistry::has("area"));
  Scene scene = floorScene();
  const auto file = writeLights("point.json", R"({"emitters": [
      {"type": "point", "name": "bulb", "position": [0, 2, 0], "intensity": [5, 4, 3]}],
      "exposure": [1]})");
  const io::LightsFileDesc desc = io::readLightsJson(file);
  ASSERT_EQ(desc.registered.size(), 1u);
  scene.lights = makeLights(desc, scene.mesh, scene.parts, scene.up, file.string());
  ASSERT_EQ(scene.lights.size(), 1u);
  const Light* l = scene.lights.all()[0];
  EXPECT_EQ(l->type(), "point");
  EXPECT_EQ(l->label(), "bulb");
  EXPECT_TRUE(l->scale()->isApprox(Vec3f(5, 4, 3)));
  // written back in the lights.json form, and read again to the same light
  LightJsonContext ctx;
  ctx.parts = &scene.parts;
  const nlohmann::json j = lightsToJson(scene.lights, ctx, {1.0});
  ASSERT_EQ(j["emitters"].size(), 1u);
  EXPECT_EQ(j["emitters"][0]["type"], "point");
  const auto again =
      LightRegistry::create(io::JsonValue(j["emitters"][0], "memory", "emitters[0]"), ctx);
  EXPECT_EQ(again->toJson(ctx), l->toJson(ctx));

  // bad input names the file and the key
  const auto bad = writeLights(
      "bad.json",
      R"({"emitters": [{"type": "pointt", "position": [0, 2, 0], "intensity": [1, 1, 1]}]})");
  const io::LightsFileDesc badDesc = io::readLightsJson(bad);
  try {
    makeLights(badDesc, scene.mesh, scene.parts, scene.up, bad.string());
    FAIL() << "an unknown light type was accepted";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("emitters[0].type"), std::string::npos) << m;
    EXPECT_NE(m.find("\"point\""), std::string::npos) << m;  // the message lists the types
  }
  const auto noPos =
      writeLights("nopos.json", R"({"emitters": [{"type": "point", "intensity": [1, 1, 1]}]})");
  EXPECT_THROW(
      makeLights(io::readLightsJson(noPos), scene.mesh, scene.parts, scene.up, noPos.string()),
      InputError);
}

TEST(Raytrace_LightRegistry, point_light_irradiance_follows_the_inverse_square_law) {
  Scene scene = floorScene();
  auto point = std::make_unique<PointLight>();
  const Vec3f pos(0.3f, 1.5f, -0.2f), I(6.0f, 4.0f, 2.0f);
  point->position = pos;
  point->intensity = I;
  scene.lights.add(std::move(point));
  ASSERT_EQ(scene.lights.registered.size(), 1u);
  const float albedo = 0.6f;
  const std::vector<PartMaterial> mats{lambert("floor", albedo)};
  const PathTracer tracer(scene, mats);
  const Camera cam = makeCamera(48, 36, 40, Vec3d(0, 3, 3), Vec3d(0, 0, 0));
  RenderOptions opt;
  opt.spp = 4;
  opt.filter = PixelFilter::Box;
  opt.filterWidth = 0.01f;  // the pixel center: the closed form is evaluated there
  const cv::Mat img = tracer.render(cam, opt);
  ASSERT_TRUE(allFinite(img));
  const GBuffer gb = renderGBuffer(tracer, cam, {1});
  int n = 0;
  double worst = 0;
  for (int y = 0; y < img.rows; ++y)
    for (int x = 0; x < img.cols; ++x) {
      if (!gb.mask[0].at<uint8_t>(y, x)) continue;
      const Vec3f eye = cam.position().cast<float>(), dir = cam.rayDirection(x, y).cast<float>();
      const float t = -eye.y() / dir.y();  // the floor y = 0
      const Vec3f p = eye + t * dir, d = pos - p;
      const float cosTheta = d.y() / d.norm();
      for (int c = 0; c < 3; ++c) {
        const float expected = albedo / kPi * I[c] * cosTheta / d.squaredNorm();
        const float got = img.at<cv::Vec3f>(y, x)[c];
        worst = std::max(worst, std::abs(got - expected) / static_cast<double>(expected));
      }
      ++n;
    }
  ASSERT_GT(n, 1000);
  // a delta light under next-event estimation has no noise: only float round-off remains
  EXPECT_LT(worst, 1e-3) << "relative error against I cos(theta) / d^2";

  // one light at a time: unit intensity, so image x intensity is the full render
  const std::vector<cv::Mat> per = tracer.renderPerLight(cam, opt);
  ASSERT_EQ(per.size(), 1u);
  for (int y = 0; y < img.rows; ++y)
    for (int x = 0; x < img.cols; ++x)
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(per[0].at<cv::Vec3f>(y, x)[c] * I[c], img.at<cv::Vec3f>(y, x)[c],
                    1e-5 + 1e-5 * img.at<cv::Vec3f>(y, x)[c]);
}

TEST(Raytrace_LightRegistry, point_light_is_shadowed_and_mixes_with_area_lights) {
  // a point light 2 m over the floor and a 1 m square blocker at 1 m: its shadow is the floor's
  // square |x|, |z| < 1
  Scene scene = floorScene();
  const int blocker = addPart(scene, "blocker");
  addQuad(scene.mesh, Vec3f(-0.5f, 1.0f, 0.5f), Vec3f(0, 0, -1), Vec3f(1, 0, 0), blocker);
  auto point = std::make_unique<PointLight>();
  const Vec3f pos(0, 2, 0);
  const float I = 4.0f, albedo = 0.5f;
  point->position = pos;
  point->intensity = Vec3f::Constant(I);
  scene.lights.add(std::move(point));
  const std::vector<PartMaterial> mats{lambert("floor", albedo), lambert("blocker", albedo)};
  const PathTracer tracer(scene, mats);
  RenderOptions opt;
  auto seen = [&](const Vec3f& p) {  // radiance leaving floor point p upwards, mean of 256 paths
    Rng rng(7);
    Vec3f sum = Vec3f::Zero();
    for (int k = 0; k < 256; ++k)
      sum += tracer.radiance(p + Vec3f(0, 0.05f, 0), Vec3f(0, -1, 0), opt, rng);
    return sum.y() / 256;
  };
  auto direct = [&](const Vec3f& p) {
    const Vec3f d = pos - p;
    return albedo / kPi * I * (d.y() / d.norm()) / d.squaredNorm();
  };
  const Vec3f lit(1.6f, 0, 0.3f), shadowed(0.2f, 0, -0.1f);
  EXPECT_NEAR(seen(lit), direct(lit), 0.05 * direct(lit));  // the blocker's underside adds a little
  EXPECT_LT(seen(shadowed), 0.1 * direct(shadowed));        // only what the blocker reflects

  // with a rectangle light too: renderPerLight lists the area light first (LightSet::all()),
  // and scale-weighted per-light images add up to the full render
  AreaLight rect;
  rect.name = "panel";
  rect.center = Vec3f(2.5f, 2.0f, 0);
  rect.edgeU = Vec3f(0.5f, 0, 0);
  rect.edgeV = Vec3f(0, 0, 0.5f);  // edgeU x edgeV = -y: emits downwards
  rect.radiance = Vec3f::Constant(10.0f);
  scene.lights.area.push_back(rect);
  const PathTracer both(scene, mats);
  const Camera cam = makeCamera(40, 30, 40, Vec3d(0, 5, 5), Vec3d(1, 0, 0));
  RenderOptions ro;
  ro.spp = 32;
  const cv::Mat full = both.render(cam, ro);
  const std::vector<cv::Mat> per = both.renderPerLight(cam, ro);
  ASSERT_EQ(per.size(), 2u);
  const double area = cv::mean(per[0])[1], pt = cv::mean(per[1])[1];
  EXPECT_GT(area, 0);
  EXPECT_GT(pt, 0);
  EXPECT_NEAR(cv::mean(full)[1], 10.0 * area + I * pt, 0.03 * cv::mean(full)[1]);
}

}  // namespace
}  // namespace ps
