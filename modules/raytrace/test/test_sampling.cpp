// Sampling building blocks of the path tracer: the per-pixel Sobol sampler is stratified and
// decorrelated; solid-angle sampling of rectangles is unbiased (irradiance against the closed
// form), including grazing points and points close to the rectangle's plane.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "photoscene/raytrace/sampler.hpp"
#include "photoscene/raytrace/spherical_rectangle.hpp"
#include "test_scenes.hpp"

namespace ps {
namespace {

// Irradiance at o (normal n) from a unit-radiance polygon, in closed form (Lambert's formula:
// E = 1/2 sum_i angle_i (unit(v_i x v_i+1) . n), v_i the unit vectors to the corners), for a
// polygon entirely above o's tangent plane.
double polygonIrradiance(const std::vector<Vec3d>& poly, const Vec3d& o, const Vec3d& n) {
  double e = 0;
  for (size_t i = 0; i < poly.size(); ++i) {
    const Vec3d a = (poly[i] - o).normalized(), b = (poly[(i + 1) % poly.size()] - o).normalized();
    const Vec3d c = a.cross(b);
    const double len = c.norm();
    if (len < 1e-15) continue;
    const double ang = std::atan2(len, a.dot(b));
    e += ang * c.dot(n) / len;
  }
  return 0.5 * std::abs(e);
}

// Solid angle of a rectangle from o (Van Oosterom-Strackee, two triangles).
double rectSolidAngle(const Vec3d& c, const Vec3d& ex, const Vec3d& ey, const Vec3d& o) {
  auto tri = [&](const Vec3d& p1, const Vec3d& p2, const Vec3d& p3) {
    const Vec3d a = p1 - o, b = p2 - o, d = p3 - o;
    const double la = a.norm(), lb = b.norm(), ld = d.norm();
    const double num = a.dot(b.cross(d));
    const double den = la * lb * ld + a.dot(b) * ld + a.dot(d) * lb + b.dot(d) * la;
    return 2 * std::atan2(std::abs(num), den);
  };
  return tri(c, c + ex, c + ex + ey) + tri(c, c + ex + ey, c + ey);
}

TEST(Raytrace_SphericalRectangle, solid_angle_and_uniform_irradiance_match_closed_form) {
  // light: corner (-0.5, 1, -0.5), edges 1 x 0.6, facing down; receivers on planes below and
  // beside it, from head-on to grazing and to 1e-3 of the light's plane
  const Vec3d corner(-0.5, 1.0, -0.5), ex(1.0, 0, 0), ey(0, 0, 0.6);
  struct Case {
    Vec3d o, n;
  };
  std::vector<Case> cases = {
      {{0, 0, 0}, {0, 1, 0}},           // head-on
      {{0.2, 0.98, -0.1}, {0, 1, 0}},   // 2 cm below the light: solid angle near 2 pi
      {{2.0, 0.999, 0.1}, {-1, 0, 0}},  // 1 mm below the light's plane, beside it
      {{3.0, 0.2, 0.0}, Vec3d(-1, 1, 0).normalized()},        // grazing
      {{0.6, 0.5, 0.4}, Vec3d(-0.3, 1, -0.2).normalized()},   // off-corner
      {{-4.0, 0.95, 2.0}, Vec3d(1, 0.2, -0.4).normalized()},  // far, 5 cm below the plane
      {{0.1, 1.5, 0.1}, {0, -1, 0}},                          // above (the other side)
      {{0.1, 1.02, 0.1}, {0, -1, 0}},                         // 2 cm above
      {{0.3, 1.02, 0.7}, {0, -1, 0}},                         // 2 cm above, off the edge
  };
  for (double px = -0.6; px <= 0.6; px += 0.3)
    for (double pz = -0.6; pz <= 0.2; pz += 0.2) cases.push_back({{px, 1.03, pz}, {0, -1, 0}});
  // the same rectangle from each corner, edges in both orders (both handednesses)
  struct Param {
    Vec3d c, a, b;
  };
  const std::vector<Param> params = {{corner, ex, ey},
                                     {corner, ey, ex},
                                     {corner + ex + ey, -ex, -ey},
                                     {corner + ex, ey, -ex},
                                     {corner + ey, -ey, ex}};
  for (const Param& pr : params)
    for (const Case& cs : cases) {
      const SphericalRectangle sr(pr.c.cast<float>(), pr.a.cast<float>(), pr.b.cast<float>(),
                                  cs.o.cast<float>());
      ASSERT_TRUE(sr.valid());
      const double S = rectSolidAngle(corner, ex, ey, cs.o);
      EXPECT_NEAR(sr.solidAngle(), S, 1e-4 * S + 1e-7) << cs.o.transpose();
      // E = S * mean(cos) over uniform solid-angle samples (stratified 128 x 128)
      const int n = 128;
      double sum = 0;
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          const Vec3f y = sr.sample((i + 0.5f) / n, (j + 0.5f) / n);
          // the point is on the rectangle
          const Vec3d yd = y.cast<double>() - corner;
          ASSERT_NEAR(yd.y(), 0.0, 1e-5);
          ASSERT_GE(yd.x(), -1e-5);
          ASSERT_LE(yd.x(), 1.0 + 1e-5);
          ASSERT_GE(yd.z(), -1e-5);
          ASSERT_LE(yd.z(), 0.6 + 1e-5);
          sum += std::max(0.0, (y.cast<double>() - cs.o).normalized().dot(cs.n));
        }
      const double E = S * sum / (n * n);
      const double ref =
          polygonIrradiance({corner, corner + ex, corner + ex + ey, corner + ey}, cs.o, cs.n);
      EXPECT_NEAR(E, ref, 0.01 * ref) << "o " << cs.o.transpose() << " S " << S;
    }
}

// Irradiance on a Lambert floor (albedo 1, so radiance = E / pi) from a rectangle emitter with
// unit radiance, through the path tracer's next-event estimation + MIS (one bounce), against
// the closed form: head-on, beside the light, grazing, 2 cm under a light facing down, and
// beside a wall light whose lower edge is 1 cm above the floor (points close to its plane).
TEST(Raytrace_SphericalRectangle,
     path_tracer_irradiance_from_rectangle_lights_matches_closed_form) {
  struct Light {
    Vec3f center, edgeU, edgeV;  // emits along edgeU x edgeV
    std::vector<Vec2f> points;   // floor points (x, z)
  };
  const std::vector<Light> lights = {
      {{0, 1.5f, 0},
       {1, 0, 0},
       {0, 0, 1},
       {{0, 0}, {1.2f, 0.7f}, {6.0f, 0.3f}}},  // ceiling light, down
      {{0, 0.02f, 0},
       {0.4f, 0, 0},
       {0, 0, 0.4f},
       {{0, 0}, {0.15f, -0.1f}, {0.3f, 0.0f}}},  // 2 cm above the floor
      {{0, 0.51f, 0},
       {0, 1, 0},
       {0, 0, 1},
       {{0.05f, 0}, {0.01f, 0.2f}, {1.0f, 0.6f}, {0.3f, 1.5f}}},  // wall light, faces +x
  };
  for (const Light& lt : lights) {
    Scene scene;
    const int floor = test::addPart(scene, "floor");
    test::addQuad(scene.mesh, Vec3f(-10, 0, 10), Vec3f(20, 0, 0), Vec3f(0, 0, -20),
                  floor);  // normal +y
    AreaLight light;
    light.name = "rect";
    light.kind = AreaLight::Kind::Rectangle;
    light.center = lt.center;
    light.edgeU = lt.edgeU;
    light.edgeV = lt.edgeV;
    light.radiance = Vec3f::Ones();
    scene.lights.area.push_back(light);
    std::vector<PartMaterial> mats{test::lambert("floor", 1.0f)};
    const PathTracer tracer(scene, mats);
    RenderOptions opt;
    opt.maxBounces = 1;  // direct light only: the floor sees nothing but the light
    const Vec3f n = light.normal();
    const Vec3f c0 = lt.center - 0.5f * lt.edgeU - 0.5f * lt.edgeV;
    const std::vector<Vec3d> poly = {c0.cast<double>(), (c0 + lt.edgeU).cast<double>(),
                                     (c0 + lt.edgeU + lt.edgeV).cast<double>(),
                                     (c0 + lt.edgeV).cast<double>()};
    for (const Vec2f& pt : lt.points) {
      const Vec3f target(pt.x(), 0, pt.y());
      ASSERT_GT((target - lt.center).dot(n), 0.0f);  // in front of the one-sided light
      // looked at from 1 cm above the floor, from the side away from the light (so the camera ray
      // passes under a light 2 cm above the floor)
      const Vec3f away = Vec3f(pt.x() - lt.center.x(), 0, pt.y() - lt.center.z()).normalized();
      const Vec3f eye =
          target + Vec3f(0, 0.01f, 0) + 0.5f * (away.allFinite() ? away : Vec3f(1, 0, 0));
      const Vec3f dir = (target - eye).normalized();
      const double ref = polygonIrradiance(poly, target.cast<double>(), Vec3d(0, 1, 0)) / kPiD;
      Rng rng(7);
      double sum = 0;
      const int samples = 20000;
      for (int k = 0; k < samples; ++k) sum += tracer.radiance(eye, dir, opt, rng).y();
      EXPECT_NEAR(sum / samples, ref, 0.01 * ref + 1e-6)
          << "light at " << lt.center.transpose() << ", point " << pt.transpose();
    }
  }
}

// Number of distinct cells hit by the first n points in a gx x gy grid.
int cellsHit(const std::vector<Vec2f>& p, int n, int gx, int gy) {
  std::set<int> cells;
  for (int i = 0; i < n; ++i)
    cells.insert(std::min(static_cast<int>(p[i].y() * gy), gy - 1) * gx +
                 std::min(static_cast<int>(p[i].x() * gx), gx - 1));
  return static_cast<int>(cells.size());
}

TEST(Raytrace_Sampler, scrambled_dimensions_are_the_scrambles_of_the_sobol_dimensions) {
  // the shortcuts the sampler takes (bit reversals that cancel) give the same bits
  Rng rng(11, 2);
  for (int k = 0; k < 100000; ++k) {
    const uint32_t i = k < 1000 ? static_cast<uint32_t>(k) : rng.nextU32();
    const uint32_t seed = rng.nextU32();
    ASSERT_EQ(sobol::scrambledDim0(i, seed), sobol::nestedUniformScramble(sobol::dim0(i), seed))
        << i << " " << seed;
    ASSERT_EQ(sobol::scrambledDim1(i, seed), sobol::nestedUniformScramble(sobol::dim1(i), seed))
        << i << " " << seed;
  }
}

TEST(Raytrace_Sampler, first_power_of_two_samples_are_stratified_nets) {
  // For every pixel and dimension: the first 16 and 64 2D points fill every cell of every
  // elementary grid 2^a x 2^b with a + b = log2 n (a (0, m, 2)-net), and the first n values of
  // a 1D dimension one per interval of width 1 / n.
  for (uint64_t pixel : {0ull, 1ull, 12345ull}) {
    SobolSampler s(3, pixel);
    for (uint32_t dim : {0u, 1u, 5u, 17u}) {
      std::vector<Vec2f> p2;
      std::vector<float> p1;
      for (uint32_t i = 0; i < 64; ++i) {
        s.startSample(i);
        const Vec2f v = s.get2D(dim);
        ASSERT_TRUE(v.x() >= 0 && v.x() < 1 && v.y() >= 0 && v.y() < 1);
        p2.push_back(v);
        p1.push_back(s.get1D(dim));
      }
      for (int m : {4, 6}) {
        const int n = 1 << m;
        for (int a = 0; a <= m; ++a)
          EXPECT_EQ(cellsHit(p2, n, 1 << a, 1 << (m - a)), n)
              << "pixel " << pixel << " dim " << dim << " n " << n << " grid " << (1 << a) << "x"
              << (1 << (m - a));
        std::set<int> bins;
        for (int i = 0; i < n; ++i) bins.insert(static_cast<int>(p1[i] * n));
        EXPECT_EQ(static_cast<int>(bins.size()), n) << "1D, pixel " << pixel << " dim " << dim;
      }
    }
  }
}

TEST(Raytrace_Sampler, pixels_and_dimensions_are_decorrelated_and_uniform) {
  // Different pixels and dimensions get different point sets; over many pixels the values are
  // uniform (mean 1/2, variance 1/12) and the two coordinates of a pair, and two dimensions of
  // one sample, are uncorrelated.
  SobolSampler a(1, 10), b(1, 11), c(2, 10);
  a.startSample(0);
  b.startSample(0);
  c.startSample(0);
  EXPECT_NE(a.get2D(0), b.get2D(0));
  EXPECT_NE(a.get2D(0), c.get2D(0));
  EXPECT_NE(a.get2D(0), a.get2D(1));
  double sx = 0, sxx = 0, sxy = 0, sd = 0;
  const int n = 20000;
  for (int px = 0; px < n; ++px) {
    SobolSampler s(9, static_cast<uint64_t>(px));
    s.startSample(static_cast<uint32_t>(px % 7));
    const Vec2f v = s.get2D(3);
    const float w = s.get1D(4);
    sx += v.x();
    sxx += v.x() * v.x();
    sxy += (v.x() - 0.5) * (v.y() - 0.5);
    sd += (v.x() - 0.5) * (w - 0.5);
  }
  EXPECT_NEAR(sx / n, 0.5, 0.01);
  EXPECT_NEAR(sxx / n - (sx / n) * (sx / n), 1.0 / 12, 0.005);
  EXPECT_NEAR(sxy / n, 0.0, 0.005);
  EXPECT_NEAR(sd / n, 0.0, 0.005);
}

TEST(Raytrace_Sampler, stratified_sampler_lowers_pixel_noise) {
  // A Lambert floor under a rectangle light, 16 spp: the per-pixel noise of the render (RMSE
  // against a 1024-spp render) is well below that of independent sampling's expectation
  // (variance ~ 1 / spp, measured from 16 spp renders with different seeds would be the same).
  Scene scene;
  const int floor = test::addPart(scene, "floor");
  test::addQuad(scene.mesh, Vec3f(-5, 0, 5), Vec3f(10, 0, 0), Vec3f(0, 0, -10), floor);
  AreaLight light;
  light.name = "rect";
  light.kind = AreaLight::Kind::Rectangle;
  light.center = Vec3f(0, 1.0f, 0);
  light.edgeU = Vec3f(1, 0, 0);
  light.edgeV = Vec3f(0, 0, 1);  // faces down
  light.radiance = Vec3f(5, 5, 5);
  scene.lights.area.push_back(light);
  std::vector<PartMaterial> mats{test::lambert("floor", 0.8f)};
  const PathTracer tracer(scene, mats);
  const Camera cam = test::makeCamera(32, 24, 30, Vec3d(0, 2.5, 3), Vec3d(0, 0, 0));
  RenderOptions opt;
  opt.maxBounces = 1;
  opt.spp = 1024;
  const cv::Mat ref = tracer.render(cam, opt);
  double e4 = 0, e16 = 0;
  for (uint64_t seed : {1, 2, 3}) {
    opt.seed = seed;
    opt.spp = 4;
    e4 += std::pow(cv::norm(tracer.render(cam, opt), ref, cv::NORM_L2), 2);
    opt.spp = 16;
    e16 += std::pow(cv::norm(tracer.render(cam, opt), ref, cv::NORM_L2), 2);
  }
  // independent samples: e16 = e4 / 4; stratified: clearly faster than 1 / spp
  EXPECT_LT(e16, 0.6 * e4 / 4) << "squared error 4 spp " << e4 << ", 16 spp " << e16;
}

}  // namespace
}  // namespace ps
