// The shared shading terms (core/shading.hpp) and luminance (core/color.hpp).
#include <gtest/gtest.h>

#include <cmath>

#include "photoscene/core/color.hpp"
#include "photoscene/core/shading.hpp"

namespace ps {
namespace {

TEST(Core_Luminance, rec709_weights_sum_to_one_and_white_keeps_its_value) {
  EXPECT_NEAR(kLuminanceWeights[0] + kLuminanceWeights[1] + kLuminanceWeights[2], 1.0, 1e-12);
  EXPECT_NEAR(luminance(Vec3f(0.7f, 0.7f, 0.7f)), 0.7f, 1e-6f);
  EXPECT_NEAR(luminance(0.25, 0.25, 0.25), 0.25, 1e-12);
  // green dominates, blue counts least
  EXPECT_GT(luminance(Vec3f(0, 1, 0)), luminance(Vec3f(1, 0, 0)));
  EXPECT_GT(luminance(Vec3f(1, 0, 0)), luminance(Vec3f(0, 0, 1)));
  // the float form sums exactly as the expression it replaced
  const float r = 0.3f, g = 0.6f, b = 0.9f;
  EXPECT_EQ(luminance(r, g, b), 0.2126f * r + 0.7152f * g + 0.0722f * b);
  EXPECT_EQ(luminance(cv::Vec3f(r, g, b)), luminance(Vec3f(r, g, b)));
}

// Integral over the hemisphere of f(cos theta) d omega, by the midpoint rule in cos theta.
template <class F>
double hemisphere(F f, int n = 200000) {
  double s = 0;
  for (int i = 0; i < n; ++i) {
    const double c = (i + 0.5) / n;
    s += f(static_cast<float>(c));
  }
  return 2 * kPiD * s / n;
}

TEST(Core_Shading, ggx_d_is_a_normal_distribution_for_every_roughness) {
  // the projected microfacet area is the macro surface's: integral of D(h) cos(h) = 1
  for (float alpha : {0.05f, 0.2f, 0.5f, 0.8f, 1.0f}) {
    const float a2 = alpha * alpha;
    EXPECT_NEAR(hemisphere([&](float c) { return shading::ggxD(c, a2) * c; }), 1.0, 2e-3)
        << "alpha " << alpha;
  }
}

TEST(Core_Shading, smith_g1_limits_and_k_is_g1_over_4_cos) {
  for (float alpha : {0.01f, 0.3f, 1.0f}) {
    const float a2 = alpha * alpha;
    EXPECT_NEAR(shading::smithG1(1.0f, a2), 1.0f, 1e-6f);  // no masking at normal incidence
    EXPECT_EQ(shading::smithG1(0.0f, a2), 0.0f);           // full masking at grazing
    for (float c : {0.1f, 0.5f, 0.9f}) {
      const float g = shading::smithG1(c, a2);
      EXPECT_GT(g, 0.0f);
      EXPECT_LE(g, 1.0f + 1e-6f);
      EXPECT_NEAR(shading::specularK(c, alpha).value, g / (4 * c), 1e-6f);
    }
  }
  EXPECT_EQ(shading::schlickWeight(1.0f), 0.0f);
  EXPECT_EQ(shading::schlickWeight(0.0f), 1.0f);
  EXPECT_EQ(shading::schlickWeight(-0.5f), 1.0f);  // clamped
  EXPECT_NEAR(shading::schlickWeight(0.5f), 1.0f / 32, 1e-7f);
}

// The render layer's backward pass differentiates these terms: central differences in double
// around float evaluations, relative tolerance.
TEST(Core_Shading, gradients_match_finite_differences) {
  const float h = 1e-3f;
  auto check = [&](const char* what, float analytic, float plus, float minus) {
    const double fd = (double(plus) - double(minus)) / (2.0 * h);
    EXPECT_NEAR(analytic, fd, 2e-2 * std::max(1.0, std::abs(fd))) << what;
  };
  for (float alpha : {0.1f, 0.35f, 0.7f})
    for (float c : {0.2f, 0.55f, 0.9f}) {
      const shading::TermGrad d = shading::ggxDGrad(c, alpha);
      EXPECT_FLOAT_EQ(d.value, shading::ggxD(c, alpha * alpha));
      check("dD/dc", d.dCos, shading::ggxD(c + h, alpha * alpha),
            shading::ggxD(c - h, alpha * alpha));
      check("dD/dalpha", d.dAlpha, shading::ggxD(c, (alpha + h) * (alpha + h)),
            shading::ggxD(c, (alpha - h) * (alpha - h)));
      const shading::TermGrad g = shading::smithG1Grad(c, alpha);
      EXPECT_FLOAT_EQ(g.value, shading::smithG1(c, alpha * alpha));
      check("dG1/dc", g.dCos, shading::smithG1(c + h, alpha * alpha),
            shading::smithG1(c - h, alpha * alpha));
      check("dG1/dalpha", g.dAlpha, shading::smithG1(c, (alpha + h) * (alpha + h)),
            shading::smithG1(c, (alpha - h) * (alpha - h)));
      const shading::TermGrad k = shading::specularK(c, alpha);
      check("dK/dc", k.dCos, shading::specularK(c + h, alpha).value,
            shading::specularK(c - h, alpha).value);
      check("dK/dalpha", k.dAlpha, shading::specularK(c, alpha + h).value,
            shading::specularK(c, alpha - h).value);
    }
}

}  // namespace
}  // namespace ps
