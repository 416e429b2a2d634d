// Physics of the path tracer on analytic scenes: white furnace, emitting closed sphere, form
// factor of a square light; determinism; G-buffers.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include <map>

#include "test_scenes.hpp"

namespace ps {
namespace {

using namespace ps::test;

// Mean of channel 1 over pixels where `mask` is set.
double maskedMean(const cv::Mat& img, const cv::Mat& mask, int channel = 1) {
  double s = 0;
  int n = 0;
  for (int y = 0; y < img.rows; ++y)
    for (int x = 0; x < img.cols; ++x)
      if (mask.at<uint8_t>(y, x)) {
        s += img.at<cv::Vec3f>(y, x)[channel];
        ++n;
      }
  return n ? s / n : 0.0;
}

// A unit sphere (part "sphere") under a constant environment of `radiance`; white 2 is the
// furnace.
Scene furnaceScene(const Vec3f& radiance = Vec3f(2.0f, 2.0f, 2.0f)) {
  Scene s;
  const int part = addPart(s, "sphere");
  addSphere(s.mesh, Vec3f(0, 0, 0), 1.0f, part, false, 32, 64);
  EnvironmentLight env;
  env.radiance = radiance;
  s.lights.environment = env;
  return s;
}

TEST(Raytrace_PathTracer, white_furnace_lambert_sphere) {
  const Scene scene = furnaceScene();
  for (float albedo : {1.0f, 0.5f}) {
    std::vector<PartMaterial> mats{lambert("sphere", albedo)};
    const PathTracer tracer(scene, mats);
    const Camera cam = makeCamera(64, 64, 110, Vec3d(0, 0.5, 4), Vec3d(0, 0, 0));
    RenderOptions opt;
    opt.spp = 64;
    opt.maxBounces = opt.maxDiffuseBounces = 64;
    const cv::Mat img = tracer.render(cam, opt);
    ASSERT_TRUE(allFinite(img));
    const GBuffer gb = renderGBuffer(tracer, cam, {1});
    cv::Mat inner;  // sphere pixels away from the silhouette
    cv::erode(gb.mask[0], inner, cv::Mat::ones(5, 5, CV_8U));
    ASSERT_GT(cv::countNonZero(inner), 1000);
    const double mean = maskedMean(img, inner);
    EXPECT_NEAR(mean, albedo * 2.0, 0.01 * albedo * 2.0) << "albedo " << albedo;
    cv::Mat bg = gb.partId < 0,
            bgInner;  // away from the silhouette (the pixel filter is 3 px wide)
    cv::erode(bg, bgInner, cv::Mat::ones(7, 7, CV_8U));
    EXPECT_NEAR(maskedMean(img, bgInner), 2.0, 1e-5);
  }
}

TEST(Raytrace_PathTracer, white_furnace_with_image_environment_and_ggx) {
  // Same furnace with an environment *image* of constant value (exercises its importance
  // sampling) and a specular lobe: albedo 1 diffuse + F0 = 0 is exact; with metallic 1 and
  // albedo 1, GGX may only lose energy (<= L), and not much at low roughness.
  Scene scene = furnaceScene();
  scene.lights.environment->image = cv::Mat(32, 64, CV_32FC3, cv::Scalar::all(1.0));
  scene.lights.environment->radiance = Vec3f::Constant(2.0f);
  PartMaterial metal = PartMaterial::defaultGray("sphere");
  metal.albedo = Vec3f::Ones();
  metal.metallic = 1.0f;
  metal.roughness = 0.3f;
  for (int k = 0; k < 2; ++k) {
    std::vector<PartMaterial> mats{k == 0 ? lambert("sphere", 1.0f) : metal};
    const PathTracer tracer(scene, mats);
    const Camera cam = makeCamera(48, 48, 45, Vec3d(0, 0.5, 4), Vec3d(0, 0, 0));
    RenderOptions opt;
    opt.spp = 64;
    const cv::Mat img = tracer.render(cam, opt);
    ASSERT_TRUE(allFinite(img));
    const GBuffer gb = renderGBuffer(tracer, cam, {1});
    cv::Mat inner;
    cv::erode(gb.mask[0], inner, cv::Mat::ones(5, 5, CV_8U));
    const double mean = maskedMean(img, inner);
    if (k == 0)
      EXPECT_NEAR(mean, 2.0, 0.02);
    else {
      EXPECT_LE(mean, 2.0 * 1.01);
      EXPECT_GE(mean, 2.0 * 0.9);
    }
  }
}

TEST(Raytrace_PathTracer, closed_emitting_sphere_converges_to_Le_over_one_minus_albedo) {
  Scene scene;
  const int part = addPart(scene, "shell");
  addSphere(scene.mesh, Vec3f(0, 0, 0), 1.0f, part, true, 24, 48);
  AreaLight light;
  light.name = "shell";
  light.kind = AreaLight::Kind::Part;
  light.partId = part;
  light.radiance = Vec3f(1.0f, 1.0f, 1.0f);
  scene.lights.area.push_back(light);
  for (float a : {0.5f, 0.8f}) {
    std::vector<PartMaterial> mats{lambert("shell", a)};
    const PathTracer tracer(scene, mats);
    const Camera cam = makeCamera(24, 24, 20, Vec3d(0.1, 0.2, 0.3), Vec3d(0.5, 0, -1));
    RenderOptions opt;
    opt.spp = 64;
    opt.maxBounces = opt.maxDiffuseBounces = 1000;
    opt.rouletteDepth = 2;
    const cv::Mat img = tracer.render(cam, opt);
    ASSERT_TRUE(allFinite(img));
    const double mean = cv::mean(img)[1];
    EXPECT_NEAR(mean, 1.0 / (1.0 - a), 0.01 / (1.0 - a)) << "albedo " << a;
  }
}

// Point-to-rectangle form factor (parallel planes), for a point below corner (0, 0) of a
// rectangle [0, X] x [0, Y] at distance 1 (signed X, Y).
double cornerFormFactor(double X, double Y) {
  const double a = std::sqrt(1 + X * X), b = std::sqrt(1 + Y * Y);
  return (X / a * std::atan(Y / a) + Y / b * std::atan(X / b)) / (2 * kPiD);
}
double rectFormFactor(double px, double pz, double x0, double x1, double z0, double z1, double h) {
  auto f = [&](double x, double z) { return cornerFormFactor((x - px) / h, (z - pz) / h); };
  return f(x1, z1) - f(x0, z1) - f(x1, z0) + f(x0, z0);
}

TEST(Raytrace_PathTracer, lambert_plane_under_square_light_matches_form_factor) {
  Scene scene;
  const int floor = addPart(scene, "floor");
  addQuad(scene.mesh, Vec3f(-5, 0, 5), Vec3f(10, 0, 0), Vec3f(0, 0, -10), floor);  // normal +y
  AreaLight light;
  light.name = "square";
  light.kind = AreaLight::Kind::Rectangle;
  const float h = 1.5f, side = 1.0f;
  light.center = Vec3f(0, h, 0);
  light.edgeU = Vec3f(side, 0, 0);
  light.edgeV = Vec3f(0, 0, side);  // u x v = -y: faces down
  light.radiance = Vec3f(10, 10, 10);
  scene.lights.area.push_back(light);
  std::vector<PartMaterial> mats{lambert("floor", 1.0f)};
  const PathTracer tracer(scene, mats);
  RenderOptions opt;
  opt.maxBounces = 4;
  for (const Vec2f& pt : {Vec2f(0, 0), Vec2f(0.3f, -0.2f), Vec2f(1.2f, 0.7f)}) {
    const Vec3f target(pt.x(), 0, pt.y());
    const Vec3f eye = target + Vec3f(0.8f, 0.6f, 0.3f);
    const Vec3f dir = (target - eye).normalized();
    Rng base(11);
    double sum = 0;
    const int n = 40000;
    for (int i = 0; i < n; ++i) {
      Rng rng = base.split(i);
      sum += tracer.radiance(eye, dir, opt, rng).y();
    }
    const double F = rectFormFactor(pt.x(), pt.y(), -0.5, 0.5, -0.5, 0.5, h);
    // Lambertian albedo 1: L_o = E / pi = Le * F
    EXPECT_NEAR(sum / n, 10.0 * F, 0.01 * 10.0 * F) << "point " << pt.transpose();
  }
}

TEST(Raytrace_PathTracer, fixed_seed_same_image_on_any_thread_count) {
  Scene scene = furnaceScene();
  std::vector<PartMaterial> mats{lambert("sphere", 0.7f)};
  const PathTracer tracer(scene, mats);
  const Camera cam = makeCamera(40, 30, 40, Vec3d(0, 0.5, 4), Vec3d(0, 0, 0));
  RenderOptions opt;
  opt.spp = 4;
  opt.seed = 42;
  cv::Mat a, b, c;
  {
    ThreadLimit one(1);
    a = tracer.render(cam, opt);
  }
  b = tracer.render(cam, opt);
  opt.seed = 43;
  c = tracer.render(cam, opt);
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(a, c, cv::NORM_INF), 0.0);
}

// A box room with a textured, normal-mapped, rotated floor, a metal and a mirror-smooth part,
// degenerate triangles and UVs, a window and two lights: nothing non-finite comes out, and the
// per-light images add up to the full render.
Scene boxRoom(std::vector<PartMaterial>* mats) {
  Scene s;
  const int floor = addPart(s, "floor"), walls = addPart(s, "walls"),
            ceiling = addPart(s, "ceiling");
  const int window = addPart(s, "window"), lamp = addPart(s, "lamp"), junk = addPart(s, "junk");
  Mesh& m = s.mesh;
  const float X = 4, Y = 2.5f, Z = 3;
  addQuad(m, Vec3f(0, 0, Z), Vec3f(X, 0, 0), Vec3f(0, 0, -Z), floor, X, Z);   // up
  addQuad(m, Vec3f(0, Y, 0), Vec3f(X, 0, 0), Vec3f(0, 0, Z), ceiling, X, Z);  // down
  addQuad(m, Vec3f(0, 0, 0), Vec3f(X, 0, 0), Vec3f(0, Y, 0), walls, X, Y);    // +z
  addQuad(m, Vec3f(X, 0, Z), Vec3f(-X, 0, 0), Vec3f(0, Y, 0), walls, X, Y);   // -z
  addQuad(m, Vec3f(0, 0, Z), Vec3f(0, 0, -Z), Vec3f(0, Y, 0), walls, Z, Y);   // +x
  // east wall with a 1 x 1 m window opening at (x = X, y 1..2, z 1..2)
  const Vec3f e(X, 0, 0);
  addQuad(m, e, Vec3f(0, 0, 1), Vec3f(0, Y, 0), walls);
  addQuad(m, e + Vec3f(0, 0, 2), Vec3f(0, 0, Z - 2), Vec3f(0, Y, 0), walls);
  addQuad(m, e + Vec3f(0, 0, 1), Vec3f(0, 0, 1), Vec3f(0, 1, 0), walls);
  addQuad(m, e + Vec3f(0, 2, 1), Vec3f(0, 0, 1), Vec3f(0, Y - 2, 0), walls);
  addQuad(m, e + Vec3f(0, 1, 1), Vec3f(0, 0, 1), Vec3f(0, 1, 0), window);
  addQuad(m, Vec3f(1, Y - 0.01f, 1), Vec3f(0.5f, 0, 0), Vec3f(0, 0, 0.5f), lamp);  // normal -y
  // junk: a degenerate triangle, a triangle with degenerate uvs, a small glossy box face
  addTriangle(m, Vec3f(1, 1, 1), Vec3f(1, 1, 1), Vec3f(2, 1, 1), junk);
  addTriangle(m, Vec3f(1, 0.5f, 1), Vec3f(2, 0.5f, 1.2f), Vec3f(1.5f, 1.0f, 1.5f), junk,
              Vec2f(0, 0), Vec2f(0, 0), Vec2f(0, 0));
  addQuad(m, Vec3f(2.5f, 0.01f, 2), Vec3f(0.5f, 0.3f, 0), Vec3f(0, 0, -0.5f), junk);
  AreaLight l1;
  l1.name = "lamp";
  l1.kind = AreaLight::Kind::Part;
  l1.partId = lamp;
  l1.radiance = Vec3f(20, 18, 15);
  AreaLight l2;
  l2.name = "rect";
  l2.kind = AreaLight::Kind::Rectangle;
  l2.center = Vec3f(3, Y - 0.02f, 2);
  l2.edgeU = Vec3f(0.4f, 0, 0);
  l2.edgeV = Vec3f(0, 0, -0.4f);  // faces down
  l2.radiance = Vec3f(10, 10, 12);
  s.lights.area = {l1, l2};
  EnvironmentLight env;
  env.image = cv::Mat(16, 32, CV_32FC3);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 32; ++x)
      env.image.at<cv::Vec3f>(y, x) = cv::Vec3f(0.2f + x / 32.0f, 1.0f - y / 16.0f, 0.5f);
  env.radiance = Vec3f(3, 3, 3);
  env.windowParts = {window};
  s.lights.environment = env;
  mats->assign(s.parts.size(), PartMaterial());
  for (const Part& p : s.parts) (*mats)[p.id] = PartMaterial::defaultGray(p.name);
  PartMaterial& f = (*mats)[floor];
  cv::Mat alb(8, 8, CV_32FC3), nrm(8, 8, CV_32FC3), rough(8, 8, CV_32FC1);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) {
      alb.at<cv::Vec3f>(y, x) =
          ((x + y) % 2) ? cv::Vec3f(0.8f, 0.6f, 0.4f) : cv::Vec3f(0.1f, 0.1f, 0.1f);
      const Vec3f n = Vec3f(0.3f * std::sin(x), 0.3f * std::cos(y), 1).normalized();
      nrm.at<cv::Vec3f>(y, x) = cv::Vec3f(n.x(), n.y(), n.z());
      rough.at<float>(y, x) = (x % 3 == 0) ? 0.0f : 0.6f;
    }
  f.albedoMap = FloatTexture(alb);
  f.normalMap = FloatTexture(nrm);
  f.roughnessMap = FloatTexture(rough);
  f.uv.rotationDeg = 30;
  f.uv.scale = Vec2f(0.7f, 0.5f);
  f.uv.offset = Vec2f(0.1f, 0.2f);
  (*mats)[junk].albedo = Vec3f(0.9f, 0.9f, 0.9f);
  (*mats)[junk].metallic = 1.0f;
  (*mats)[junk].roughness = 0.0f;
  for (int p : {window, lamp}) {
    (*mats)[p].albedo = Vec3f::Zero();
    (*mats)[p].metallic = 1.0f;
  }
  (*mats)[walls].roughness = 1.0f;
  return s;
}

// The box room, its path tracer and a w x h camera looking at the window wall.
struct BoxRoomView {
  std::vector<PartMaterial> mats;
  Scene scene;
  PathTracer tracer;  // refers to scene and mats: the struct is neither copied nor moved
  Camera cam;
  BoxRoomView(int w, int h, double focal = 30)
      : scene(boxRoom(&mats)),
        tracer(scene, mats),
        cam(makeCamera(w, h, focal, Vec3d(0.3, 1.4, 2.7), Vec3d(3.5, 1.0, 0.8))) {}
  BoxRoomView(const BoxRoomView&) = delete;
  BoxRoomView& operator=(const BoxRoomView&) = delete;
};

TEST(Raytrace_PathTracer, box_room_finite_and_per_light_images_add_up) {
  const BoxRoomView room(48, 36);
  RenderOptions opt;
  opt.spp = 48;
  const cv::Mat full = room.tracer.render(room.cam, opt);
  ASSERT_TRUE(allFinite(full));
  const std::vector<cv::Mat> per = room.tracer.renderPerLight(room.cam, opt);
  ASSERT_EQ(per.size(), 3u);  // lamp, rect, environment
  cv::Mat sum(full.size(), CV_32FC3, cv::Scalar::all(0));
  for (int i = 0; i < 2; ++i) {
    ASSERT_TRUE(allFinite(per[i]));
    const Vec3f r = *room.scene.lights.area[i].radiance;
    std::vector<cv::Mat> ch;
    cv::split(per[i], ch);
    for (int c = 0; c < 3; ++c) ch[c] *= r[c];
    cv::Mat scaled;
    cv::merge(ch, scaled);
    sum += scaled;
  }
  {
    std::vector<cv::Mat> ch;
    cv::split(per[2], ch);
    for (int c = 0; c < 3; ++c) ch[c] *= room.scene.lights.environment->radiance[c];
    cv::Mat scaled;
    cv::merge(ch, scaled);
    sum += scaled;
  }
  // unbiased estimates of the same image: the means agree to the noise level
  const cv::Scalar a = cv::mean(full), b = cv::mean(sum);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], 0.03 * a[c]) << "channel " << c;
  EXPECT_GT(a[0], 0.01);
}

// The largest |z| over blocks x channels of a - b, where a and b are independent estimates of
// the same image: z = mean(d) / (sd(d) / sqrt(n)) over the n pixels of a block (pixels are
// independent: every pixel has its own scrambled sequence). The tolerance is the blocks' own
// sample standard deviation, not a constant.
double maxBlockZ(const cv::Mat& a, const cv::Mat& b, int block) {
  double worst = 0;
  for (int by = 0; by + block <= a.rows; by += block)
    for (int bx = 0; bx + block <= a.cols; bx += block)
      for (int c = 0; c < 3; ++c) {
        double s = 0, s2 = 0;
        const int n = block * block;
        for (int y = by; y < by + block; ++y)
          for (int x = bx; x < bx + block; ++x) {
            const double d = a.at<cv::Vec3f>(y, x)[c] - b.at<cv::Vec3f>(y, x)[c];
            s += d;
            s2 += d * d;
          }
        const double mean = s / n, var = std::max(0.0, (s2 - n * mean * mean) / (n - 1));
        if (var <= 0) {
          if (mean != 0) return std::numeric_limits<double>::infinity();
          continue;
        }
        worst = std::max(worst, std::abs(mean) / std::sqrt(var / n));
      }
  return worst;
}

cv::Mat scaled(const cv::Mat& img, const Vec3f& s) {
  cv::Mat out;
  cv::multiply(img, cv::Scalar(s.x(), s.y(), s.z()), out);
  return out;
}

// 48 tests (12 blocks x 3 channels) per comparison: |z| < 4.5 has a false-alarm rate of
// about 3e-4 per comparison for normal block means (and the seeds are fixed: no flakiness).
constexpr double kMaxZ = 4.5;

TEST(Raytrace_PerLight, one_trace_equals_one_light_at_a_time_with_the_same_numbers) {
  // The per-light trace draws every number of light i's estimate as a render of light i alone
  // does: the images are the same, bit for bit (a contribution given to the wrong light, or a
  // MIS weight with the wrong selection probability, changes them).
  const BoxRoomView room(48, 36);
  RenderOptions opt;
  opt.spp = 8;
  opt.seed = 5;
  RenderStats stTogether;
  const std::vector<cv::Mat> per = room.tracer.renderPerLight(room.cam, opt, &stTogether);
  ASSERT_EQ(per.size(), 3u);  // lamp (part), rect, environment through the window
  uint64_t raysAlone = 0;
  for (int i = 0; i < 3; ++i) {
    RenderOptions o = opt;
    o.lights = LightSelection::one(i);
    RenderStats st;
    const cv::Mat alone = room.tracer.render(room.cam, o, &st);
    raysAlone += st.rays;
    ASSERT_TRUE(allFinite(per[i]));
    EXPECT_GT(cv::mean(alone)[1], 1e-4) << "light " << i;  // every light is seen
    EXPECT_EQ(cv::norm(per[i], alone, cv::NORM_INF), 0.0) << "light " << i;
  }
  // one camera path and one extension ray per vertex for all lights, not one per light
  EXPECT_LT(stTogether.rays, raysAlone);
}

// RenderOptions::pixels: the traced pixels hold the whole render's values to the bit (each
// pixel's sampler is its own), the others stay 0, in both render() and renderPerLight().
TEST(Raytrace_PerLight, traced_pixels_equal_the_whole_render_and_the_rest_stay_black) {
  const BoxRoomView room(48, 36);
  RenderOptions opt;
  opt.spp = 4;
  opt.seed = 9;
  const std::vector<cv::Mat> whole = room.tracer.renderPerLight(room.cam, opt);
  const cv::Mat wholeSum = room.tracer.render(room.cam, opt);
  RenderOptions some = opt;
  some.pixels = cv::Mat::zeros(36, 48, CV_8UC1);
  cv::circle(some.pixels, {20, 15}, 9, cv::Scalar(255), cv::FILLED);
  for (int y = 0; y < 36; y += 3) some.pixels.at<uint8_t>(y, (7 * y) % 48) = 1;  // odd pixels
  some.pixels.at<uint8_t>(35, 47) = 255;                                         // the last one
  auto blackOutside = [&](const cv::Mat& image) {  // what the traced pixels alone should give
    cv::Mat out = image.clone();
    out.setTo(cv::Scalar::all(0), some.pixels == 0);
    return out;
  };
  const std::vector<cv::Mat> part = room.tracer.renderPerLight(room.cam, some);
  ASSERT_EQ(part.size(), whole.size());
  for (size_t i = 0; i < part.size(); ++i) {
    const cv::Mat expected = blackOutside(whole[i]);
    EXPECT_GT(cv::norm(expected, cv::NORM_INF), 0.0) << "light " << i;
    EXPECT_EQ(cv::norm(part[i], expected, cv::NORM_INF), 0.0) << "light " << i;
  }
  EXPECT_EQ(cv::norm(room.tracer.render(room.cam, some), blackOutside(wholeSum), cv::NORM_INF),
            0.0);
  RenderOptions wrong = opt;
  wrong.pixels = cv::Mat::ones(36, 47, CV_8UC1);
  EXPECT_THROW(room.tracer.render(room.cam, wrong), Exception);
}

TEST(Raytrace_PerLight, per_light_images_match_one_light_renders_and_add_up_within_noise) {
  const BoxRoomView room(64, 48);
  RenderOptions opt;
  opt.spp = 32;
  opt.seed = 1;
  const std::vector<cv::Mat> per = room.tracer.renderPerLight(room.cam, opt);
  ASSERT_EQ(per.size(), 3u);
  const std::vector<Vec3f> scale = {*room.scene.lights.area[0].radiance, *room.scene.lights.area[1].radiance,
                                    room.scene.lights.environment->radiance};
  cv::Mat sum(per[0].size(), CV_32FC3, cv::Scalar::all(0));
  for (int i = 0; i < 3; ++i) {
    RenderOptions o = opt;
    o.seed = 2;  // independent of the per-light trace
    o.lights = LightSelection::one(i);
    const cv::Mat alone = room.tracer.render(room.cam, o);
    EXPECT_LT(maxBlockZ(per[i], alone, 16), kMaxZ) << "light " << i;
    // the test sees a 10 % error in the lamp's and the environment's images (the small
    // rectangle's, 0.16 m^2 seen mostly through one bounce, is too noisy at 32 spp for that;
    // the test above checks it to the bit)
    if (i != 1) {
      EXPECT_GT(maxBlockZ(per[i] * 1.1, alone, 16), kMaxZ) << "light " << i;
    }
    sum += scaled(per[i], scale[i]);
  }
  // the all-lights render (lights picked by power: another estimator of the same image)
  RenderOptions o = opt;
  o.seed = 3;
  const cv::Mat all = room.tracer.render(room.cam, o);
  EXPECT_LT(maxBlockZ(sum, all, 16), kMaxZ);
  // ... and a light's image at another light's radiance is seen: the lamp's at the rect's
  cv::Mat wrong = scaled(per[0], scale[1]) + scaled(per[1], scale[1]) + scaled(per[2], scale[2]);
  EXPECT_GT(maxBlockZ(wrong, all, 16), kMaxZ);
}

TEST(Raytrace_GBuffer, depth_parts_derivatives_and_coverage) {
  std::vector<PartMaterial> mats;
  const Scene scene = boxRoom(&mats);
  const PathTracer tracer(scene, mats);
  const Camera cam = makeCamera(64, 48, 40, Vec3d(2, 1.5, 2.9), Vec3d(2, 0.0, 0.5));
  const GBuffer gb = renderGBuffer(tracer, cam, {4});
  const int floor = 0;
  ASSERT_FALSE(gb.mask[floor].empty());
  int checked = 0;
  for (int y = 0; y < cam.height(); ++y)
    for (int x = 0; x < cam.width(); ++x) {
      if (gb.partId.at<int>(y, x) != floor) continue;
      // the floor is y = 0: the world point is where the pixel ray meets it
      const Vec3d d = cam.rayDirection(x, y);
      const Vec3d o = cam.position();
      const double t = -o.y() / d.y();
      const Vec3d p = o + t * d;
      const cv::Vec3f gp = gb.position.at<cv::Vec3f>(y, x);
      EXPECT_NEAR(gp[0], p.x(), 1e-4);
      EXPECT_NEAR(gp[2], p.z(), 1e-4);
      EXPECT_NEAR(gb.depth.at<float>(y, x), cam.toCamera(p).z(), 1e-4);
      // floor uv = (x, Z - z): d(uv)/d(pixel) from the neighbouring ray's floor point
      const Vec3d dx = cam.rayDirection(x + 1, y);
      const Vec3d px = o + (-o.y() / dx.y()) * dx;
      const cv::Vec2f duv = gb.duvdx.at<cv::Vec2f>(y, x);
      EXPECT_NEAR(duv[0], px.x() - p.x(), 1e-4);
      EXPECT_NEAR(duv[1], -(px.z() - p.z()), 1e-4);
      const cv::Vec3f n = gb.normalGeo.at<cv::Vec3f>(y, x);
      EXPECT_NEAR(n[1], 1.0f, 1e-5);
      const cv::Vec3f tg = gb.tangent.at<cv::Vec3f>(y, x);
      EXPECT_NEAR(tg[0], 1.0f, 1e-4);  // dP/du = +x
      ++checked;
    }
  EXPECT_GT(checked, 500);
  // coverage: in [0, 1], sums to 1 over parts where every sub-ray hits, 1 inside masks away from
  // edges
  cv::Mat total(cam.height(), cam.width(), CV_32FC1, cv::Scalar(0));
  for (const cv::Mat& c : gb.coverage)
    if (!c.empty()) total += c;
  double minv, maxv;
  cv::minMaxLoc(total, &minv, &maxv);
  EXPECT_NEAR(maxv, 1.0, 1e-5);
  cv::Mat inner;
  cv::erode(gb.mask[floor], inner, cv::Mat::ones(3, 3, CV_8U));
  cv::Mat cov = gb.coverage[floor];
  cv::minMaxLoc(cov, &minv, &maxv, nullptr, nullptr, inner);
  EXPECT_NEAR(minv, 1.0, 1e-6);
  // anti-aliased edge: some floor pixels are partially covered
  int partial = 0;
  for (int y = 0; y < cov.rows; ++y)
    for (int x = 0; x < cov.cols; ++x)
      if (cov.at<float>(y, x) > 0.01f && cov.at<float>(y, x) < 0.99f) ++partial;
  EXPECT_GT(partial, 10);
}

TEST(Raytrace_IncidentLight, part_list_traces_only_those_parts_and_keeps_their_values) {
  std::vector<PartMaterial> mats;
  const Scene scene = boxRoom(&mats);
  const PathTracer tracer(scene, mats);
  const Camera cam = makeCamera(64, 48, 40, Vec3d(2, 1.5, 2.9), Vec3d(2, 0.0, 0.5));
  const GBuffer gb = renderGBuffer(tracer, cam, {1});
  IncidentLightOptions o;
  o.stride = 8;
  o.samplesPerBin = 1;
  o.render.seed = 3;
  const IncidentLightGrid all = computeIncidentLight(tracer, gb, cam, o);
  const int floor = scene.partId("floor");
  o.parts.assign(scene.parts.size(), 0);
  o.parts[floor] = 1;
  const IncidentLightGrid some = computeIncidentLight(tracer, gb, cam, o);
  int onFloor = 0, elsewhere = 0;
  const size_t bins = static_cast<size_t>(o.thetaBins) * o.phiBins;
  for (int gy = 0; gy < all.height; ++gy)
    for (int gx = 0; gx < all.width; ++gx) {
      const size_t k = static_cast<size_t>(gy) * all.width + gx;
      const int part = gb.partId.at<int>(all.pixelY(gy, cam.height()), all.pixelX(gx, cam.width()));
      if (part == floor) {
        ++onFloor;
        ASSERT_TRUE(some.valid[k]);
        for (size_t b = 0; b < bins; ++b)  // the same numbers, point by point
          ASSERT_EQ(some.radiance[k * bins + b], all.radiance[k * bins + b]);
      } else {
        EXPECT_FALSE(some.valid[k]);
        elsewhere += all.valid[k];
      }
    }
  EXPECT_GT(onFloor, 5);
  EXPECT_GT(elsewhere, 5);
}

TEST(Raytrace_Material, uv_transform_and_texture_orientation) {
  // t = (0, 0) is the bottom-left corner of the map: row H-1, column 0.
  cv::Mat img(4, 4, CV_32FC1, cv::Scalar(0));
  img.at<float>(3, 0) = 1.0f;  // bottom-left texel
  const FloatTexture tex(img);
  EXPECT_NEAR(tex.sample(Vec2f(0.125f, 0.125f)).x(), 1.0f, 1e-6);
  EXPECT_NEAR(tex.sample(Vec2f(0.125f, 0.875f)).x(), 0.0f, 1e-6);
  EXPECT_NEAR(tex.sample(Vec2f(1.125f, -0.875f)).x(), 1.0f, 1e-6);  // period 1
  UvTransform t;
  t.rotationDeg = 90;
  t.scale = Vec2f(2, 3);
  t.offset = Vec2f(0.1f, 0.2f);
  const Vec2f r = t.apply(Vec2f(1, 0));  // S: (2, 0); R90: (0, 2); + offset
  EXPECT_NEAR(r.x(), 0.1f, 1e-6);
  EXPECT_NEAR(r.y(), 2.2f, 1e-6);
  // tangent frame of t: for dP/du = +x, dP/dv = +z and a 90 degree rotation, dP/dt_u = -z / ...
  Vec3f T, B;
  UvTransform rot;
  rot.rotationDeg = 90;
  ASSERT_TRUE(tangentFrame(Vec3f(1, 0, 0), Vec3f(0, 0, 1), Vec3f(0, -1, 0), rot, &T, &B));
  // t = R90 uv: t_u = -v, t_v = u, so dP/dt_u = -dP/dv = -z and dP/dt_v = dP/du = +x
  EXPECT_NEAR(T.z(), -1.0f, 1e-5);
  EXPECT_NEAR(B.x(), 1.0f, 1e-5);
}

}  // namespace
}  // namespace ps

namespace ps {
namespace {

TEST(Raytrace_IncidentLight, furnace_grid_is_constant_and_shades_lambert_exactly) {
  using namespace ps::test;
  Scene scene = furnaceScene(Vec3f(2.0f, 1.0f, 0.5f));
  std::vector<PartMaterial> mats{lambert("sphere", 0.6f)};
  const PathTracer tracer(scene, mats);
  const Camera cam = makeCamera(32, 32, 60, Vec3d(0, 0.5, 4), Vec3d(0, 0, 0));
  const GBuffer gb = renderGBuffer(tracer, cam, {1});
  IncidentLightOptions o;
  o.stride = 4;
  o.samplesPerBin = 1;
  const IncidentLightGrid grid = computeIncidentLight(tracer, gb, cam, o);
  EXPECT_EQ(grid.width, 8);
  int points = 0;
  const MicrofacetBsdf lam(Vec3f::Constant(0.6f), Vec3f::Zero(), 1.0f);
  for (int gy = 0; gy < grid.height; ++gy)
    for (int gx = 0; gx < grid.width; ++gx) {
      if (!grid.valid[gy * grid.width + gx]) continue;
      ++points;
      // a convex sphere sees only the environment over its hemisphere (the last, grazing row may
      // dip below the facet: the shading normal of a tessellated sphere is not the face normal)
      for (int i = 0; i + 1 < grid.thetaBins; ++i)
        for (int j = 0; j < grid.phiBins; ++j) EXPECT_NEAR(grid.at(gx, gy, i, j).x(), 2.0f, 1e-5);
      const Vec3f Lo = grid.shade(gx, gy, lam, Vec3f(0.3f, 0.1f, 0.95f).normalized(), 4);
      EXPECT_NEAR(Lo.x(), 0.6f * 2.0f, 0.02 * 1.2);
      EXPECT_NEAR(Lo.z(), 0.6f * 0.5f, 0.02 * 0.3);
      const ShRadiance sh = projectToSh(grid, gx, gy, 3);
      EXPECT_TRUE(sh.eval(Vec3f(0, 0, 1)).allFinite());
    }
  EXPECT_GT(points, 10);
}


TEST(Raytrace_IncidentLight, light_sampling_lowers_the_grids_noise_without_bias) {
  // The box room's lamps are small: a bin's few path samples find them or not, and the shading
  // a grid point gives varies from seed to seed (and so from point to point: blotches). Sampling
  // the lamps as well (MIS) must keep the expectation and cut that spread.
  const BoxRoomView room(48, 36);
  const GBuffer gb = renderGBuffer(room.tracer, room.cam, {1});
  const MicrofacetBsdf white(Vec3f::Constant(1.0f), Vec3f::Zero(), 1.0f);
  const int seeds = 6;
  auto shading = [&](int directSamples) {
    std::vector<std::vector<double>> perPoint;  // [point][seed] shaded luminance
    for (int s = 0; s < seeds; ++s) {
      IncidentLightOptions o;
      o.stride = 4;
      o.samplesPerBin = 2;
      o.directSamples = directSamples;
      o.render.seed = 17 + s;
      const IncidentLightGrid g = computeIncidentLight(room.tracer, gb, room.cam, o);
      perPoint.resize(g.valid.size());
      for (int gy = 0; gy < g.height; ++gy)
        for (int gx = 0; gx < g.width; ++gx) {
          const size_t k = static_cast<size_t>(gy) * g.width + gx;
          if (!g.valid[k]) continue;
          const Vec3f Lo = g.shade(gx, gy, white, Vec3f(0, 0, 1), 1);
          EXPECT_TRUE(Lo.allFinite());
          perPoint[k].push_back(luminance(Lo));
        }
    }
    return perPoint;
  };
  const auto paths = shading(0), mis = shading(32);
  double meanPaths = 0, meanMis = 0, relPaths = 0, relMis = 0;
  int points = 0;
  auto stats = [](const std::vector<double>& v, double* mean, double* sd) {
    *mean = 0;
    for (double x : v) *mean += x / v.size();
    double q = 0;
    for (double x : v) q += (x - *mean) * (x - *mean);
    *sd = std::sqrt(q / (v.size() - 1));
  };
  for (size_t k = 0; k < paths.size(); ++k) {
    if (paths[k].size() != static_cast<size_t>(seeds)) continue;
    ASSERT_EQ(mis[k].size(), paths[k].size());
    double m0, s0, m1, s1;
    stats(paths[k], &m0, &s0);
    stats(mis[k], &m1, &s1);
    if (m0 <= 0) continue;
    meanPaths += m0;
    meanMis += m1;
    relPaths += s0 / m0;
    relMis += s1 / std::max(m1, 1e-9);
    ++points;
  }
  ASSERT_GT(points, 50);
  relPaths /= points;
  relMis /= points;
  std::printf("grid points %d: mean shading %.4f (paths) %.4f (MIS); spread over seeds %.1f %% "
              "-> %.1f %%\n",
              points, meanPaths / points, meanMis / points, 100 * relPaths, 100 * relMis);
  // the same light on average (the paths' own noise over 6 x ~100 points: about 1 %)
  EXPECT_NEAR(meanMis / meanPaths, 1.0, 0.03);
  // and far less noise
  EXPECT_LT(relMis, 0.5 * relPaths);
}

// sRGB 0-255 RMSE (what the evaluation scores), over pixels where mask is set (all if empty).
double srgbRmse(const cv::Mat& a, const cv::Mat& b, const cv::Mat& mask = cv::Mat()) {
  const cv::Mat sa = linearToSrgb(a, CV_32F), sb = linearToSrgb(b, CV_32F);
  double s = 0;
  int n = 0;
  for (int y = 0; y < a.rows; ++y)
    for (int x = 0; x < a.cols; ++x) {
      if (!mask.empty() && !mask.at<uint8_t>(y, x)) continue;
      const cv::Vec3f d = sa.at<cv::Vec3f>(y, x) - sb.at<cv::Vec3f>(y, x);
      s += d.dot(d) / 3.0;
      ++n;
    }
  return n ? 255.0 * std::sqrt(s / n) : 0.0;
}

RenderOptions samples(int spp, uint64_t seed) {
  RenderOptions o;
  o.spp = spp;
  o.seed = seed;
  return o;
}

TEST(Raytrace_RenderGuides, the_render_gives_the_denoiser_guides_that_match_its_geometry) {
  const BoxRoomView room(64, 48);
  const RenderOptions opt = samples(8, 3);
  DenoiseGuides g;
  const cv::Mat img = room.tracer.render(room.cam, opt, nullptr, &g);
  // asking for the guides does not change the image
  EXPECT_EQ(cv::norm(img, room.tracer.render(room.cam, opt), cv::NORM_INF), 0.0);
  ASSERT_EQ(g.albedo.size(), img.size());
  ASSERT_EQ(g.variance.type(), CV_32FC1);
  GBufferOptions go;
  go.coverageSamples = 4;
  go.passWindows = true;
  const GBuffer gb = renderGBuffer(room.tracer, room.cam, go);
  const int walls = 1;  // the room is closed but for the window: part -1 is seen through it
  int wallPixels = 0, windowPixels = 0;
  double windowAlbedo = 0;  // 1 where a sample sees no surface
  for (int y = 1; y + 1 < img.rows; ++y)
    for (int x = 1; x + 1 < img.cols; ++x) {
      // interior pixels: the 3x3 neighbourhood shows one face of one part, or only the
      // environment through the window (the pixel filter reaches 0.75 px)
      const int part = gb.partId.at<int>(y, x);
      bool interior = part < 0 || (!gb.coverage[part].empty() &&
                                   gb.coverage[part].at<float>(y, x) == 1.0f);
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          interior &= gb.partId.at<int>(y + dy, x + dx) == part &&
                      gb.normalShading.at<cv::Vec3f>(y + dy, x + dx) ==
                          gb.normalShading.at<cv::Vec3f>(y, x);
      if (!interior) continue;
      const float z = g.depth.at<float>(y, x);
      if (part == walls) {
        ++wallPixels;
        const cv::Vec3f a = g.albedo.at<cv::Vec3f>(y, x);
        const MaterialSample ms = room.mats[walls].evaluate(Vec2f(0, 0));
        const Vec3f expected = ms.diffuseColor() + ms.f0();
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(a[k], expected[k], 1e-5);
        EXPECT_NEAR(z, gb.depth.at<float>(y, x), 0.02 * gb.depth.at<float>(y, x));
        const cv::Vec3f n = g.normal.at<cv::Vec3f>(y, x), m = gb.normalShading.at<cv::Vec3f>(y, x);
        EXPECT_GT(n.dot(m), 0.999);
      }
      if (part < 0) {  // the environment through the window: no surface, passed through
        ++windowPixels;
        EXPECT_EQ(z, 0.0f);
        windowAlbedo += g.albedo.at<cv::Vec3f>(y, x)[1];
      }
      EXPECT_GE(g.variance.at<float>(y, x), 0.0f);
      EXPECT_TRUE(std::isfinite(g.variance.at<float>(y, x)));
    }
  EXPECT_GT(wallPixels, 200);
  EXPECT_GT(windowPixels, 10);
  EXPECT_GT(windowAlbedo / windowPixels, 0.99);
}

TEST(Raytrace_RenderGuides, the_variance_guide_is_the_variance_of_the_pixel_mean) {
  // Across independent seeds the pixel's luminance varies by the variance of its mean; the
  // guide estimates it from one render's samples as if they were independent (the Sobol
  // samples are stratified, so the true variance is lower: the guide errs on the safe side,
  // within a small factor). And it falls as 1 / spp.
  const BoxRoomView room(32, 24);
  RenderOptions opt;
  opt.spp = 16;
  const int seeds = 12;
  std::vector<cv::Mat> lum;
  cv::Mat guideMean(room.cam.height(), room.cam.width(), CV_64FC1, cv::Scalar(0));
  for (int s = 0; s < seeds; ++s) {
    opt.seed = 100 + s;
    DenoiseGuides g;
    const cv::Mat img = room.tracer.render(room.cam, opt, nullptr, &g);
    cv::Mat l(img.size(), CV_64FC1);
    for (int y = 0; y < img.rows; ++y)
      for (int x = 0; x < img.cols; ++x) {
        const cv::Vec3f c = img.at<cv::Vec3f>(y, x);
        l.at<double>(y, x) = luminance(double(c[0]), double(c[1]), double(c[2]));
      }
    lum.push_back(l);
    cv::Mat gv;
    g.variance.convertTo(gv, CV_64F);
    guideMean += gv / seeds;
  }
  double empirical = 0, guide = 0;
  for (int y = 0; y < room.cam.height(); ++y)
    for (int x = 0; x < room.cam.width(); ++x) {
      double m = 0, m2 = 0;
      for (const cv::Mat& l : lum) m += l.at<double>(y, x) / seeds;
      for (const cv::Mat& l : lum) m2 += std::pow(l.at<double>(y, x) - m, 2) / (seeds - 1);
      empirical += m2;
      guide += guideMean.at<double>(y, x);
    }
  ASSERT_GT(empirical, 0);
  EXPECT_GT(guide / empirical, 0.8);
  EXPECT_LT(guide / empirical, 4.0);
  // 4x the samples: a quarter of the variance (the guide's mean over the image)
  opt.seed = 100;
  opt.spp = 64;
  DenoiseGuides g64;
  room.tracer.render(room.cam, opt, nullptr, &g64);
  EXPECT_NEAR(cv::mean(g64.variance)[0] / cv::mean(guideMean)[0], 0.25, 0.08);
}

TEST(Raytrace_RenderGuides, denoised_low_spp_beats_raw_four_times_the_samples) {
  // The property at test size: 8 spp denoised with the render's own guides is closer to
  // a 1024-spp reference than 32 spp raw, on RMSE (sRGB 0-255) over the image.
  const BoxRoomView room(96, 72, 40);
  RenderOptions opt = samples(1024, 4242);
  const cv::Mat ref = room.tracer.render(room.cam, opt);
  opt.seed = 1;
  opt.spp = 8;
  DenoiseGuides g;
  const cv::Mat noisy = room.tracer.render(room.cam, opt, nullptr, &g);
  const cv::Mat clean = denoise(g, noisy);
  opt.spp = 32;
  const cv::Mat raw32 = room.tracer.render(room.cam, opt);
  const double eNoisy = srgbRmse(noisy, ref), eClean = srgbRmse(clean, ref),
               e32 = srgbRmse(raw32, ref);
  EXPECT_LT(eClean, e32) << "raw 8: " << eNoisy << ", denoised 8: " << eClean << ", raw 32: " << e32;
  EXPECT_LT(eClean, 0.8 * eNoisy) << "raw 8: " << eNoisy << ", denoised 8: " << eClean << ", raw 32: " << e32;
}

TEST(Raytrace_Adaptive, threshold_zero_is_the_plain_render_and_a_threshold_spends_fewer_samples) {
  const BoxRoomView room(64, 48);
  RenderOptions opt = samples(64, 9);
  RenderStats plainStats, adaptiveStats;
  const cv::Mat plain = room.tracer.render(room.cam, opt, &plainStats);
  EXPECT_EQ(plainStats.samples, uint64_t(64) * 48 * 64);
  opt.adaptiveMinSpp = 16;
  opt.adaptiveThreshold = 0.0f;  // off
  EXPECT_EQ(cv::norm(plain, room.tracer.render(room.cam, opt), cv::NORM_INF), 0.0);
  opt.adaptiveThreshold = 0.1f;
  const cv::Mat adaptive = room.tracer.render(room.cam, opt, &adaptiveStats);
  ASSERT_TRUE(allFinite(adaptive));
  EXPECT_LT(adaptiveStats.samples, plainStats.samples * 3 / 4);
  EXPECT_GE(adaptiveStats.samples, uint64_t(64) * 48 * 16);
  // the same image within noise (a stopped pixel keeps the mean of the samples it took)
  EXPECT_LT(maxBlockZ(adaptive, plain, 16), kMaxZ);
  // and the samples went where the noise is: at the same number of samples, the adaptive image
  // is closer to a reference than a uniform one
  RenderOptions ro = opt;
  ro.adaptiveThreshold = 0;
  ro.spp = 1024;
  ro.seed = 4242;
  const cv::Mat ref = room.tracer.render(room.cam, ro);
  ro.seed = 9;
  ro.spp = static_cast<int>(adaptiveStats.samples / (64 * 48));
  const cv::Mat uniform = room.tracer.render(room.cam, ro);
  EXPECT_LT(srgbRmse(adaptive, ref), srgbRmse(uniform, ref))
      << ro.spp << " spp uniform against adaptive with the same samples";
  std::string err;
  opt.adaptiveMinSpp = 1;
  EXPECT_FALSE(opt.IsValid(&err));
  opt.adaptiveMinSpp = 16;
  opt.adaptiveThreshold = std::numeric_limits<float>::quiet_NaN();
  EXPECT_FALSE(opt.IsValid(&err));
}


TEST(Raytrace_IncidentLight, albedo_sensitivity_matches_finite_differences) {
  // What the grid's irradiance owes to a part's diffuse albedo (IncidentLightGrid::
  // albedoSensitivity) must be the derivative of the irradiance with respect to that albedo's
  // log scale: checked by central differences, scaling the plain walls' albedo and the textured,
  // partly glossy floor's albedo map by 1 +- 0.3, summed over the grid and over 10 seeds (the
  // paths' noise between traces at different albedos is what limits the check).
  BoxRoomView room(48, 36);
  const GBuffer gb = renderGBuffer(room.tracer, room.cam, {1});
  const int walls = 1, floor = 0;
  auto totalIrradiance = [&](const IncidentLightGrid& g) {
    Vec3d e = Vec3d::Zero();
    for (int gy = 0; gy < g.height; ++gy)
      for (int gx = 0; gx < g.width; ++gx)
        if (g.valid[static_cast<size_t>(gy) * g.width + gx]) e += g.irradiance(gx, gy).cast<double>();
    return e;
  };
  const float h = 0.3f;  // the traces' noise over the difference falls with h; s^3 terms err 3 %
  std::map<int, Vec3d> analytic, fd;
  Vec3d total = Vec3d::Zero();
  for (int seed = 0; seed < 10; ++seed) {
    IncidentLightOptions o;
    o.stride = 4;
    o.samplesPerBin = 4;
    o.render.seed = 5 + seed;
    o.albedoSensitivity = true;
    const IncidentLightGrid g = computeIncidentLight(room.tracer, gb, room.cam, o);
    ASSERT_EQ(g.sensitivityStart.size(), g.valid.size() + 1);
    for (size_t k = 0; k + 1 < g.sensitivityStart.size(); ++k)
      for (int e = g.sensitivityStart[k]; e < g.sensitivityStart[k + 1]; ++e) {
        ASSERT_TRUE(g.sensitivityValue[e].allFinite());
        EXPECT_GE(g.sensitivityValue[e].minCoeff(), 0.0f);
        const auto it = analytic.try_emplace(g.sensitivityPart[e], Vec3d::Zero()).first;
        it->second += g.sensitivityValue[e].cast<double>();
      }
    o.albedoSensitivity = false;
    const Vec3d base = totalIrradiance(computeIncidentLight(room.tracer, gb, room.cam, o));
    EXPECT_LT((totalIrradiance(g) - base).norm(), 1e-6 * base.norm());  // recording changes nothing
    total += base;
    for (int part : {walls, floor}) {
      PartMaterial& m = room.mats[part];
      const PartMaterial keep = m;
      auto scaled = [&](float s) {
        m = keep;
        if (m.albedoMap.empty())
          m.albedo = keep.albedo * s;
        else
          m.albedoScale = keep.albedoScale * s;
        return totalIrradiance(computeIncidentLight(room.tracer, gb, room.cam, o));
      };
      const Vec3d d = (scaled(1 + h) - scaled(1 - h)) / (2 * h);
      m = keep;
      fd.try_emplace(part, Vec3d::Zero()).first->second += d;
    }
  }
  for (int part : {walls, floor}) {
    const Vec3d an = analytic[part], f = fd[part];
    std::printf("part %d: d E / d ln a analytic (%.3f %.3f %.3f) finite differences (%.3f %.3f "
                "%.3f) of E (%.3f %.3f %.3f)\n",
                part, an.x(), an.y(), an.z(), f.x(), f.y(), f.z(), total.x(), total.y(),
                total.z());
    for (int c = 0; c < 3; ++c) {
      EXPECT_GT(an[c], 0.05 * total[c]);  // the walls and the floor do light the room
      EXPECT_NEAR(an[c] / f[c], 1.0, 0.1) << "part " << part << " channel " << c;
    }
  }
}
}  // namespace
}  // namespace ps
