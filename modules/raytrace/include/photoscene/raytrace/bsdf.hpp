// The contract's BRDF: Lambert diffuse + GGX microfacet specular (UE4 / Karis 2013).
//
// All directions are unit vectors in the local shading frame: +Z is the shading normal, wo
// points towards the viewer, wi towards the light. eval() returns f(wo, wi) without the cosine.
//
//   D(h)     = alpha^2 / (pi ((n.h)^2 (alpha^2 - 1) + 1)^2),       alpha = max(roughness^2, kMinAlpha)
//   G        = G1(wo) G1(wi),  G1(w) = 2 / (1 + sqrt(1 + alpha^2 tan^2(theta_w)))   (separable Smith)
//   F(wo.h)  = F0 + (min(1, 50 F0_green) - F0) (1 - wo.h)^5                 (Schlick, UE4's form:
//              F0 below 2% is treated as shadowing, so F0 = 0 (specular 0) gives no specular at all)
//   f        = diffuse / pi + D G F / (4 cos_o cos_i)
//
// Sampling picks the specular lobe with a probability from the lobes' estimated albedos and then
// draws the visible normals of GGX (Heitz 2018) or a cosine-weighted direction; pdf() is the
// combined one-sample density of wi (solid angle).
#pragma once

#include <cmath>

#include "photoscene/core/math.hpp"

namespace ps {

inline constexpr float kMinAlpha = 1e-3f;

/// alpha = roughness^2, clamped to [kMinAlpha, 1].
inline float ggxAlpha(float roughness) {
  const float r = clampv(std::isfinite(roughness) ? roughness : 1.0f, 0.0f, 1.0f);
  return std::max(r * r, kMinAlpha);
}
/// GGX normal distribution D(h) for a local half vector h (h.z = cos theta_h).
float ggxD(const Vec3f& h, float alpha);
/// Smith masking G1(w) for the GGX distribution.
float smithG1(const Vec3f& w, float alpha);
/// Schlick Fresnel in UE4's form (see above).
Vec3f schlickFresnel(const Vec3f& f0, float cosTheta);
/// Draws a visible normal of GGX for the view direction wo (wo.z > 0), u1, u2 in [0, 1).
Vec3f sampleGgxVisibleNormal(const Vec3f& wo, float alpha, float u1, float u2);

struct BsdfSample {
  Vec3f wi = Vec3f::Zero();
  Vec3f f = Vec3f::Zero();  ///< f(wo, wi), no cosine
  float pdf = 0;            ///< solid-angle density of wi (the combined one-sample pdf)
  bool specular = false;    ///< the specular lobe was chosen
};

/// Lambert + GGX at one shading point.
class MicrofacetBsdf {
 public:
  /// @param diffuse  albedo * (1 - metallic), linear RGB in [0, 1]
  /// @param f0       Fresnel at normal incidence, linear RGB in [0, 1]
  /// @param roughness perceptual roughness in [0, 1] (alpha = roughness^2)
  /// @param burleyDiffuse  replace Lambert by Burley's (Disney) diffuse with this roughness, as
  ///                       Blender's Principled BSDF v1 does (NOT the contract's model: only for
  ///                       measuring how much of a difference to Cycles that accounts for)
  MicrofacetBsdf(const Vec3f& diffuse, const Vec3f& f0, float roughness, bool burleyDiffuse = false);

  Vec3f eval(const Vec3f& wo, const Vec3f& wi) const;
  /// The specular term alone (D G F / (4 cos cos)).
  Vec3f evalSpecular(const Vec3f& wo, const Vec3f& wi) const;
  float pdf(const Vec3f& wo, const Vec3f& wi) const;
  /// Draws wi for wo with three uniform numbers. Returns false when no direction was produced
  /// (wo below the surface, or the specular sample fell below the horizon).
  bool sample(const Vec3f& wo, float uLobe, float u1, float u2, BsdfSample* s) const;

  float alpha() const { return alpha_; }
  const Vec3f& diffuse() const { return diffuse_; }
  const Vec3f& f0() const { return f0_; }
  /// True when the BRDF is zero everywhere (a perfect absorber such as emitters and windows).
  bool black() const { return diffuse_.maxCoeff() <= 0.0f && f0_.maxCoeff() <= 0.0f; }
  /// Probability of the specular lobe for this wo.
  float specularProbability(const Vec3f& wo) const;

 private:
  Vec3f diffuse_, f0_;
  float alpha_, roughness_;
  bool noSpecular_, burley_;
  Vec3f evalDiffuse(const Vec3f& wo, const Vec3f& wi) const;
};

}  // namespace ps
