// The microfacet shading terms, written once: Lambert, the GGX (Trowbridge-Reitz) normal
// distribution D, the separable Smith masking G1 for GGX, the specular term K = G1 / (4 cos),
// Schlick's Fresnel weight, and the derivatives the render layer's backward pass needs, next to
// each forward term. The path tracer (raytrace/bsdf.cpp), the differentiable render layer
// (render/render_layer.cpp, forward and backward) and the graph previews (graph/preview.cpp) all
// evaluate these; a change here changes all three alike.
//
// Conventions: every term takes cosines against the shading normal (c = n.h for D, c = n.w for
// G1 and K) and alpha = roughness^2 (or alpha^2 where named a2). The forms are branch-free and
// inline so that the render layer's loops over directions vectorise: callers zero the terms of
// directions below the horizon (c <= 0) themselves. With c in [0, 1] and alpha > 0 no term
// divides by zero.
//
//   D(c)  = a2 / (pi q^2),               q = c^2 (a2 - 1) + 1
//   G1(c) = 2 c / (c + sqrt(c^2 (1 - a2) + a2))
//   K(c)  = G1(c) / (4 c) = 1 / (2 (c + s)),   s = sqrt(c^2 (1 - a2) + a2)
//   Fc(c) = (1 - c)^5, c clamped to [0, 1]      (F = F0 + (F90 - F0) Fc)
//   Lambert: albedo / pi
#pragma once

#include <algorithm>
#include <cmath>

#include "photoscene/core/math.hpp"

namespace ps::shading {

/// Lambert's BRDF for unit albedo: 1 / pi.
inline constexpr float kLambert = kInvPi;

/// Schlick's Fresnel weight (1 - c)^5 with c clamped to [0, 1].
inline float schlickWeight(float c) {
  const float m = std::min(1.0f, std::max(0.0f, 1.0f - c));
  const float m2 = m * m;
  return m2 * m2 * m;
}

/// GGX D for c = n.h >= 0 and a2 = alpha^2.
inline float ggxD(float c, float a2) {
  const float iq = 1.0f / (c * c * (a2 - 1) + 1);
  return a2 * kInvPi * iq * iq;
}

/// Smith G1 for GGX, c = n.w >= 0 and a2 = alpha^2.
inline float smithG1(float c, float a2) {
  return 2 * c / (c + std::sqrt(c * c * (1 - a2) + a2));
}

/// A term and its partial derivatives in the cosine and in alpha.
struct TermGrad {
  float value, dCos, dAlpha;
};

/// D and dD/dc, dD/dalpha, for c = n.h >= 0 and alpha (not squared).
inline TermGrad ggxDGrad(float c, float alpha) {
  const float a2 = alpha * alpha, dScale = a2 * kInvPi;
  const float q = c * c * (a2 - 1) + 1;
  const float iq = 1.0f / q;
  const float iq2 = iq * iq, iq3 = iq2 * iq;
  return {dScale * iq2, -4 * dScale * (a2 - 1) * c * iq3,
          2 * alpha * kInvPi * iq3 * (q - 2 * a2 * c * c)};
}

/// G1 and dG1/dc, dG1/dalpha, for c = n.w >= 0 and alpha > 0 (not squared).
inline TermGrad smithG1Grad(float c, float alpha) {
  const float a2 = alpha * alpha, oneMa2 = 1 - a2;
  const float s = std::sqrt(c * c * oneMa2 + a2);  // >= alpha > 0
  const float ics = 1.0f / (c + s);
  const float is = 1.0f / s;
  const float dsdc = c * oneMa2 * is, dsda = alpha * (1 - c * c) * is;
  return {2 * c * ics, 2 * (s - c * dsdc) * ics * ics, -2 * c * dsda * ics * ics};
}

/// K = G1(c) / (4 c) and dK/dc, dK/dalpha (c >= 0; finite at c = 0).
inline TermGrad specularK(float c, float alpha) {
  const float a2 = alpha * alpha;
  const float s = std::sqrt(std::max(0.0f, c * c + a2 * (1 - c * c)));
  const float cs = c + s;
  const float dsdc = s > 0 ? c * (1 - a2) / s : 0.0f;
  const float dsda = s > 0 ? alpha * (1 - c * c) / s : 0.0f;
  return {0.5f / cs, -0.5f * (1 + dsdc) / (cs * cs), -0.5f * dsda / (cs * cs)};
}

}  // namespace ps::shading
