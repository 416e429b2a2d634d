#include "photoscene/raytrace/bsdf.hpp"
#include "photoscene/core/color.hpp"

#include <algorithm>

#include "photoscene/core/color.hpp"
#include "photoscene/core/shading.hpp"

namespace ps {

namespace {
inline float safeSqrt(float x) { return std::sqrt(std::max(0.0f, x)); }
}  // namespace

// D, G1 and Schlick's weight are core/shading.hpp's, shared with the render layer and previews.
float ggxD(const Vec3f& h, float alpha) {
  if (h.z() <= 0) return 0.0f;
  return shading::ggxD(h.z(), alpha * alpha);
}

float smithG1(const Vec3f& w, float alpha) {
  if (w.z() <= 0) return 0.0f;
  return shading::smithG1(w.z(), alpha * alpha);
}

Vec3f schlickFresnel(const Vec3f& f0, float cosTheta) {
  const float fc = shading::schlickWeight(cosTheta);
  const float f90 = std::min(1.0f, 50.0f * f0.y());
  return f0 + (Vec3f::Constant(f90) - f0) * fc;
}

Vec3f sampleGgxVisibleNormal(const Vec3f& wo, float alpha, float u1, float u2) {
  const Vec3f vh = Vec3f(alpha * wo.x(), alpha * wo.y(), wo.z()).normalized();
  const float lensq = vh.x() * vh.x() + vh.y() * vh.y();
  const Vec3f t1 = lensq > 1e-12f ? Vec3f(Vec3f(-vh.y(), vh.x(), 0) / std::sqrt(lensq)) : Vec3f(1, 0, 0);
  const Vec3f t2 = vh.cross(t1);
  const float r = std::sqrt(u1);
  const float phi = 2.0f * kPi * u2;
  const float p1 = r * std::cos(phi);
  float p2 = r * std::sin(phi);
  const float s = 0.5f * (1.0f + vh.z());
  p2 = (1.0f - s) * safeSqrt(1.0f - p1 * p1) + s * p2;
  const Vec3f nh = p1 * t1 + p2 * t2 + safeSqrt(1.0f - p1 * p1 - p2 * p2) * vh;
  Vec3f ne(alpha * nh.x(), alpha * nh.y(), std::max(1e-6f, nh.z()));
  return ne.normalized();
}

MicrofacetBsdf::MicrofacetBsdf(const Vec3f& diffuse, const Vec3f& f0, float roughness, bool burleyDiffuse)
    : diffuse_(diffuse.cwiseMax(0.0f).cwiseMin(1.0f)),
      f0_(f0.cwiseMax(0.0f).cwiseMin(1.0f)),
      alpha_(ggxAlpha(roughness)),
      roughness_(clampv(std::isfinite(roughness) ? roughness : 1.0f, 0.0f, 1.0f)),
      burley_(burleyDiffuse) {
  noSpecular_ = f0_.maxCoeff() <= 0.0f;
}

Vec3f MicrofacetBsdf::evalDiffuse(const Vec3f& wo, const Vec3f& wi) const {
  if (!burley_) return diffuse_ * shading::kLambert;
  Vec3f h = wo + wi;
  const float hl = h.norm();
  const float cd = hl > 1e-8f ? wi.dot(h / hl) : 0.0f;
  const float fd90 = 0.5f + 2.0f * roughness_ * cd * cd;
  auto w = [](float c) {
    const float m = clampv(1.0f - c, 0.0f, 1.0f);
    return m * m * m * m * m;
  };
  return diffuse_ * (kInvPi * (1 + (fd90 - 1) * w(wi.z())) * (1 + (fd90 - 1) * w(wo.z())));
}

float MicrofacetBsdf::specularProbability(const Vec3f& wo) const {
  if (noSpecular_) return 0.0f;
  const float ls = luminance(schlickFresnel(f0_, std::max(0.0f, wo.z())));
  const float ld = luminance(diffuse_);
  if (ld <= 0.0f) return 1.0f;
  return clampv(ls / (ls + ld), 0.1f, 0.9f);
}

Vec3f MicrofacetBsdf::evalSpecular(const Vec3f& wo, const Vec3f& wi) const {
  if (noSpecular_ || wo.z() <= 0 || wi.z() <= 0) return Vec3f::Zero();
  Vec3f h = wo + wi;
  const float hl = h.norm();
  if (!(hl > 1e-8f)) return Vec3f::Zero();
  h /= hl;
  const float D = ggxD(h, alpha_);
  const float G = smithG1(wo, alpha_) * smithG1(wi, alpha_);
  const Vec3f F = schlickFresnel(f0_, std::max(0.0f, wo.dot(h)));
  return F * (D * G / (4.0f * wo.z() * wi.z()));
}

Vec3f MicrofacetBsdf::eval(const Vec3f& wo, const Vec3f& wi) const {
  if (wo.z() <= 0 || wi.z() <= 0) return Vec3f::Zero();
  return evalDiffuse(wo, wi) + evalSpecular(wo, wi);
}

float MicrofacetBsdf::pdf(const Vec3f& wo, const Vec3f& wi) const {
  if (wo.z() <= 0 || wi.z() <= 0) return 0.0f;
  const float ps = specularProbability(wo);
  float pdf = (1.0f - ps) * wi.z() * kInvPi;
  if (ps > 0) {
    Vec3f h = wo + wi;
    const float hl = h.norm();
    if (hl > 1e-8f) {
      h /= hl;
      // visible-normal density: G1(wo) D(h) max(0, wo.h) / wo.z, times the reflection Jacobian 1 / (4 wo.h)
      pdf += ps * smithG1(wo, alpha_) * ggxD(h, alpha_) / (4.0f * wo.z());
    }
  }
  return pdf;
}

bool MicrofacetBsdf::sample(const Vec3f& wo, float uLobe, float u1, float u2, BsdfSample* s) const {
  if (wo.z() <= 0) return false;
  const float ps = specularProbability(wo);
  if (uLobe < ps) {
    const Vec3f h = sampleGgxVisibleNormal(wo, alpha_, u1, u2);
    const float oh = wo.dot(h);
    if (oh <= 0) return false;
    s->wi = 2.0f * oh * h - wo;
    s->specular = true;
  } else {
    const float r = std::sqrt(u1), phi = 2.0f * kPi * u2;
    s->wi = Vec3f(r * std::cos(phi), r * std::sin(phi), safeSqrt(1.0f - u1));
    s->specular = false;
  }
  if (s->wi.z() <= 1e-7f) return false;
  s->pdf = pdf(wo, s->wi);
  if (!(s->pdf > 0) || !std::isfinite(s->pdf)) return false;
  s->f = eval(wo, s->wi);
  return s->f.allFinite();
}

}  // namespace ps
