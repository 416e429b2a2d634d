// Oklab (Ottosson 2020) from / to linear sRGB, and the Jacobian of the forward map: a perceptual
// space where lightness (L), and chroma and hue (the a, b plane) separate. Used by the colour
// draws (MaterialGraph::randomValues) and the palette prior (palette_prior.hpp).
#pragma once

#include <algorithm>
#include <cmath>

namespace ps::graphimpl {

inline constexpr float kOklabM1[3][3] = {{0.4122214708f, 0.5363325363f, 0.0514459929f},
                                         {0.2119034982f, 0.6806995451f, 0.1073969566f},
                                         {0.0883024619f, 0.2817188376f, 0.6299787005f}};
inline constexpr float kOklabM2[3][3] = {{0.2104542553f, 0.7936177850f, -0.0040720468f},
                                         {1.9779984951f, -2.4285922050f, 0.4505937099f},
                                         {0.0259040371f, 0.7827717662f, -0.8086757660f}};

/// lab = M2 cbrt(M1 c). With `jacobian` (row-major 3 x 3, d lab / d c): the cube root's derivative
/// is taken at max(lms, 1e-5) and is 0 below it (black has no finite slope), so it stays finite.
inline void linearToOklab(const float* c, float* lab, float* jacobian = nullptr) {
  float r[3], dr[3];
  for (int i = 0; i < 3; ++i) {
    const float lms = kOklabM1[i][0] * c[0] + kOklabM1[i][1] * c[1] + kOklabM1[i][2] * c[2];
    r[i] = std::cbrt(lms);
    dr[i] = lms > 1e-5f ? 1.f / (3.f * r[i] * r[i]) : 0.f;
  }
  for (int k = 0; k < 3; ++k)
    lab[k] = kOklabM2[k][0] * r[0] + kOklabM2[k][1] * r[1] + kOklabM2[k][2] * r[2];
  if (!jacobian) return;
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 3; ++j) {
      float s = 0.f;
      for (int i = 0; i < 3; ++i) s += kOklabM2[k][i] * dr[i] * kOklabM1[i][j];
      jacobian[k * 3 + j] = s;
    }
}

inline void oklabToLinear(const float* lab, float* c) {
  const float l_ = lab[0] + 0.3963377774f * lab[1] + 0.2158037573f * lab[2];
  const float m_ = lab[0] - 0.1055613458f * lab[1] - 0.0638541728f * lab[2];
  const float s_ = lab[0] - 0.0894841775f * lab[1] - 1.2914855480f * lab[2];
  const float l = l_ * l_ * l_, m = m_ * m_ * m_, s = s_ * s_ * s_;
  c[0] = 4.0767416621f * l - 3.3077115913f * m + 0.2309699292f * s;
  c[1] = -1.2684380046f * l + 2.6097574011f * m - 0.3413193965f * s;
  c[2] = -0.0041960863f * l - 0.7034186830f * m + 1.7076147713f * s;
}

}  // namespace ps::graphimpl
