// Physics of the BRDF: energy conservation, reciprocity, sampling densities that integrate to one.
#include <gtest/gtest.h>

#include "photoscene/core.hpp"
#include "photoscene/raytrace/bsdf.hpp"

namespace ps {
namespace {

Vec3f dirFromAngles(float theta, float phi) {
  return Vec3f(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
}

TEST(Raytrace_Bsdf, ggx_directional_albedo_at_most_one) {
  // Specular lobe alone with F0 = 1 (the most energy it can reflect), every roughness and angle.
  const MicrofacetBsdf spec(Vec3f::Zero(), Vec3f::Ones(), 0.5f);
  (void)spec;
  Rng rng(1);
  for (float roughness : {0.0f, 0.05f, 0.2f, 0.4f, 0.7f, 1.0f}) {
    const MicrofacetBsdf b(Vec3f::Zero(), Vec3f::Ones(), roughness);
    for (float cosO : {0.02f, 0.1f, 0.3f, 0.6f, 0.9f, 1.0f}) {
      const Vec3f wo(std::sqrt(1 - cosO * cosO), 0, cosO);
      double sum = 0;
      const int n = 40000;
      for (int i = 0; i < n; ++i) {
        BsdfSample s;
        if (!b.sample(wo, rng.uniform(), rng.uniform(), rng.uniform(), &s)) continue;
        ASSERT_TRUE(s.f.allFinite());
        ASSERT_GT(s.pdf, 0);
        sum += s.f.x() * s.wi.z() / s.pdf;
      }
      const double albedo = sum / n;
      EXPECT_LE(albedo, 1.0 + 1e-3) << "roughness " << roughness << " cos " << cosO;
      EXPECT_GT(albedo, 0.3) << "roughness " << roughness << " cos " << cosO;  // not absorbing everything
    }
  }
}

TEST(Raytrace_Bsdf, lambert_only_reflects_albedo) {
  // specular 0 (F0 = 0): no specular at all, directional albedo = diffuse albedo.
  const MicrofacetBsdf b(Vec3f::Constant(0.7f), Vec3f::Zero(), 0.3f);
  Rng rng(2);
  const Vec3f wo = dirFromAngles(1.2f, 0.3f);
  double sum = 0;
  const int n = 100000;
  for (int i = 0; i < n; ++i) {
    BsdfSample s;
    if (!b.sample(wo, rng.uniform(), rng.uniform(), rng.uniform(), &s)) continue;
    sum += s.f.y() * s.wi.z() / s.pdf;
  }
  EXPECT_NEAR(sum / n, 0.7, 1e-4);  // cosine sampling of a Lambertian: zero variance
}

TEST(Raytrace_Bsdf, reciprocal) {
  Rng rng(3);
  for (int i = 0; i < 2000; ++i) {
    const MicrofacetBsdf b(Vec3f(rng.uniform(), rng.uniform(), rng.uniform()),
                           Vec3f(rng.uniform(), rng.uniform(), rng.uniform()), rng.uniform());
    const Vec3f wo = dirFromAngles(rng.uniform(0, 1.55f), rng.uniform(0, 2 * kPi));
    const Vec3f wi = dirFromAngles(rng.uniform(0, 1.55f), rng.uniform(0, 2 * kPi));
    const Vec3f a = b.eval(wo, wi), c = b.eval(wi, wo);
    ASSERT_TRUE(a.allFinite());
    EXPECT_LE((a - c).cwiseAbs().maxCoeff(), 1e-4f * (1 + a.maxCoeff()));
  }
}

TEST(Raytrace_Bsdf, finite_at_extremes) {
  for (float r : {0.0f, 1e-4f, 1.0f})
    for (float cosO : {1e-6f, 1e-3f, 1.0f}) {
      const MicrofacetBsdf b(Vec3f::Constant(0.5f), Vec3f::Constant(0.04f), r);
      const Vec3f wo(std::sqrt(1 - cosO * cosO), 0, cosO);
      for (float cosI : {1e-6f, 1e-3f, 0.5f, 1.0f}) {
        const Vec3f wi(-std::sqrt(1 - cosI * cosI), 0, cosI);
        EXPECT_TRUE(b.eval(wo, wi).allFinite());
        EXPECT_TRUE(std::isfinite(b.pdf(wo, wi)));
        const Vec3f wr(-wo.x(), -wo.y(), wo.z());  // mirror direction: the D peak
        EXPECT_TRUE(b.eval(wo, wr).allFinite());
        EXPECT_TRUE(std::isfinite(b.pdf(wo, wr)));
      }
      Rng rng(4);
      for (int i = 0; i < 1000; ++i) {
        BsdfSample s;
        if (b.sample(wo, rng.uniform(), rng.uniform(), rng.uniform(), &s)) {
          EXPECT_TRUE(s.f.allFinite());
          EXPECT_TRUE(std::isfinite(s.pdf) && s.pdf > 0);
        }
      }
    }
}

// The sampling density integrates (over the upper hemisphere) to the fraction of samples the
// sampler produces, and the histogram of samples matches the density (chi-square).
TEST(Raytrace_Bsdf, sampling_pdf_integrates_and_matches_histogram) {
  const int nT = 12, nP = 24;
  for (float roughness : {0.45f, 0.7f, 1.0f}) {
    for (float thetaO : {0.3f, 1.2f}) {
      const MicrofacetBsdf b(Vec3f::Constant(0.3f), Vec3f::Constant(0.5f), roughness);
      const Vec3f wo = dirFromAngles(thetaO, 0.4f);
      // quadrature of the pdf per bin (theta, phi), midpoint rule, fine grid
      const int sub = 60;
      std::vector<double> expected(nT * nP, 0.0);
      double integral = 0;
      for (int i = 0; i < nT * sub; ++i) {
        const double th = (i + 0.5) * (kPiD / 2) / (nT * sub);
        for (int j = 0; j < nP * sub; ++j) {
          const double ph = (j + 0.5) * 2 * kPiD / (nP * sub);
          const double dw = std::sin(th) * (kPiD / 2) / (nT * sub) * 2 * kPiD / (nP * sub);
          const double p = b.pdf(wo, dirFromAngles(static_cast<float>(th), static_cast<float>(ph))) * dw;
          expected[(i / sub) * nP + j / sub] += p;
          integral += p;
        }
      }
      Rng rng(5);
      const int n = 200000;
      std::vector<double> hist(nT * nP, 0.0);
      int produced = 0;
      for (int k = 0; k < n; ++k) {
        BsdfSample s;
        if (!b.sample(wo, rng.uniform(), rng.uniform(), rng.uniform(), &s)) continue;
        ++produced;
        const float th = std::acos(clampv(s.wi.z(), -1.0f, 1.0f));
        float ph = std::atan2(s.wi.y(), s.wi.x());
        if (ph < 0) ph += 2 * kPi;
        const int bi = std::min(nT - 1, static_cast<int>(th / (kPi / 2) * nT));
        const int bj = std::min(nP - 1, static_cast<int>(ph / (2 * kPi) * nP));
        hist[bi * nP + bj] += 1;
      }
      EXPECT_NEAR(integral, static_cast<double>(produced) / n, 2e-3)
          << "roughness " << roughness << " theta_o " << thetaO;
      EXPECT_LE(integral, 1.0 + 1e-3);
      // chi-square over bins with enough expected counts (others pooled)
      double chi2 = 0, pooledE = 0, pooledO = 0;
      int dof = 0;
      for (int k = 0; k < nT * nP; ++k) {
        const double e = expected[k] * n;
        if (e < 5) {
          pooledE += e;
          pooledO += hist[k];
          continue;
        }
        chi2 += (hist[k] - e) * (hist[k] - e) / e;
        ++dof;
      }
      if (pooledE >= 5) {
        chi2 += (pooledO - pooledE) * (pooledO - pooledE) / pooledE;
        ++dof;
      }
      // the sample count outside the hemisphere (rejected) is not binned: one dof less
      const double limit = dof + 5.0 * std::sqrt(2.0 * dof);  // far in the tail (p << 1e-4)
      EXPECT_LT(chi2, limit) << "roughness " << roughness << " theta_o " << thetaO << " dof " << dof;
    }
  }
}

}  // namespace
}  // namespace ps
