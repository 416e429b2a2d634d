#include "photoscene/raytrace/incident_light.hpp"

#include "photoscene/core/error.hpp"
#include "photoscene/core/parallel.hpp"

namespace ps {

int IncidentLightGrid::pixelX(int gx, int imageWidth) const {
  return std::min(imageWidth - 1, gx * stride + stride / 2);
}
int IncidentLightGrid::pixelY(int gy, int imageHeight) const {
  return std::min(imageHeight - 1, gy * stride + stride / 2);
}

namespace {
Vec3f localDir(float cosT, float phi) {
  const float sinT = std::sqrt(std::max(0.0f, 1 - cosT * cosT));
  return Vec3f(sinT * std::cos(phi), sinT * std::sin(phi), cosT);
}
}  // namespace

Vec3f IncidentLightGrid::binDirection(int i, int j) const {
  const float cosT = 1.0f - (i + 0.5f) / thetaBins;
  const float phi = 2 * kPi * (j + 0.5f) / phiBins;
  return localDir(cosT, phi);
}

Vec3f IncidentLightGrid::shade(int gx, int gy, const MicrofacetBsdf& bsdf, const Vec3f& wo,
                               int sub) const {
  sub = std::max(1, sub);
  Vec3f sum = Vec3f::Zero();
  const float dOmega = binSolidAngle() / (sub * sub);
  for (int i = 0; i < thetaBins; ++i)
    for (int j = 0; j < phiBins; ++j) {
      const Vec3f& L = at(gx, gy, i, j);
      if (L.maxCoeff() <= 0) continue;
      Vec3f fc = Vec3f::Zero();
      for (int a = 0; a < sub; ++a)
        for (int b = 0; b < sub; ++b) {
          const float cosT = 1.0f - (i + (a + 0.5f) / sub) / thetaBins;
          const float phi = 2 * kPi * (j + (b + 0.5f) / sub) / phiBins;
          const Vec3f wi = localDir(cosT, phi);
          fc += bsdf.eval(wo, wi) * wi.z();
        }
      sum += L.cwiseProduct(fc) * dOmega;
    }
  return sum;
}

Vec3f IncidentLightGrid::irradiance(int gx, int gy) const {
  Vec3f e = Vec3f::Zero();
  for (int i = 0; i < thetaBins; ++i) {
    const float cosT = 1.0f - (i + 0.5f) / thetaBins;
    for (int j = 0; j < phiBins; ++j) e += at(gx, gy, i, j) * cosT;
  }
  return e * binSolidAngle();
}

IncidentLightGrid computeIncidentLight(const PathTracer& tracer, const GBuffer& gb,
                                       const Camera& camera, const IncidentLightOptions& o) {
  PS_Check(o.stride >= 1 && o.thetaBins >= 1 && o.phiBins >= 1 && o.samplesPerBin >= 1 &&
               o.directSamples >= 0,
           "bad incident-light options");
  PS_CheckEQ(gb.partId.cols, camera.width(), "G-buffer and camera sizes differ");
  PS_CheckEQ(gb.partId.rows, camera.height(), "G-buffer and camera sizes differ");
  IncidentLightGrid g;
  g.stride = o.stride;
  g.thetaBins = o.thetaBins;
  g.phiBins = o.phiBins;
  g.width = (camera.width() + o.stride - 1) / o.stride;
  g.height = (camera.height() + o.stride - 1) / o.stride;
  const size_t n = static_cast<size_t>(g.width) * g.height;
  g.radiance.assign(n * o.thetaBins * o.phiBins, Vec3f::Zero());
  g.valid.assign(n, 0);
  g.position.assign(n, Vec3f::Zero());
  g.frameT.assign(n, Vec3f::Zero());
  g.frameB.assign(n, Vec3f::Zero());
  g.frameN.assign(n, Vec3f::Zero());
  const Rng base(o.render.seed ^ 0x1ce1f00dULL);
  // The grid point's own scattering is the first bounce of the camera path the render layer
  // stands in for (render() counts it against the limits); a path traced from the point starts
  // counting at the next surface, so it gets one bounce fewer of each limit (as a diffuse
  // scatter: the lobe that carries a room's light). With the full limits the grid held one
  // diffuse bounce more than render() sees, and a fit against it chose albedos that the final
  // render shows too dark, the more so the brighter the channel (blender-room: walls 7 % dark in
  // red, 2 % in blue).
  RenderOptions afterFirst = o.render;
  afterFirst.maxBounces = std::max(0, o.render.maxBounces - 1);
  afterFirst.maxDiffuseBounces = std::max(0, o.render.maxDiffuseBounces - 1);
  std::vector<AlbedoSensitivity> pointSensitivity(o.albedoSensitivity ? n : 0);
  parallelFor(0, static_cast<int64_t>(n), [&](int64_t k) {
    const int gx = static_cast<int>(k % g.width), gy = static_cast<int>(k / g.width);
    const int px = g.pixelX(gx, camera.width()), py = g.pixelY(gy, camera.height());
    const int part = gb.partId.at<int>(py, px);
    if (part < 0) return;
    if (!o.parts.empty() && (part >= static_cast<int>(o.parts.size()) || !o.parts[part])) return;
    const cv::Vec3f p = gb.position.at<cv::Vec3f>(py, px),
                    ns = gb.normalShading.at<cv::Vec3f>(py, px);
    const cv::Vec3f ng = gb.normalGeo.at<cv::Vec3f>(py, px), tg = gb.tangent.at<cv::Vec3f>(py, px);
    const Vec3f P(p[0], p[1], p[2]), N(ns[0], ns[1], ns[2]), Ng(ng[0], ng[1], ng[2]);
    Vec3f T(tg[0], tg[1], tg[2]), B;
    if (T.squaredNorm() < 0.5f)
      orthonormalBasis(N, T, B);
    else
      B = N.cross(T);
    g.valid[k] = 1;
    g.position[k] = P;
    g.frameT[k] = T;
    g.frameB[k] = B;
    g.frameN[k] = N;
    const Vec3f org = P + Ng * (2e-5f * (1.0f + P.cwiseAbs().maxCoeff()));
    Rng rng = base.split(static_cast<uint64_t>(k));
    // direct light by multiple importance sampling: the bins' uniform directions have density
    // samplesPerBin / binSolidAngle per steradian, each light `directSamples` samples of its pdf
    const float binOmega = g.binSolidAngle();
    const int M = o.render.nextEventEstimation ? o.directSamples : 0;
    const float firstPdf = M > 0 ? o.samplesPerBin / binOmega / M : 0.0f;
    std::vector<Vec3f> direct;
    if (M > 0) {
      direct.assign(static_cast<size_t>(o.thetaBins) * o.phiBins, Vec3f::Zero());
      Rng lightRng = rng.split(0x11e7u);
      for (const DirectLightSample& s :
           tracer.sampleDirectLight(P, org, Ng, M, firstPdf, afterFirst, lightRng)) {
        const Vec3f l(s.wi.dot(T), s.wi.dot(B), s.wi.dot(N));
        if (l.z() <= 0 || s.wi.dot(Ng) <= 0) continue;  // the bins cover the shading hemisphere
        const int bi = std::min(o.thetaBins - 1, static_cast<int>((1.0f - l.z()) * o.thetaBins));
        float phi = std::atan2(l.y(), l.x());
        if (phi < 0) phi += 2 * kPi;
        const int bj = std::min(o.phiBins - 1, static_cast<int>(phi / (2 * kPi) * o.phiBins));
        // the bin's mean radiance: the integral estimate over the bin's solid angle
        direct[static_cast<size_t>(bi) * o.phiBins + bj] += s.value / (M * binOmega);
      }
    }
    AlbedoSensitivity binSensitivity, sampleSensitivity;
    AlbedoSensitivity* const sens = o.albedoSensitivity ? &sampleSensitivity : nullptr;
    for (int i = 0; i < o.thetaBins; ++i)
      for (int j = 0; j < o.phiBins; ++j) {
        Vec3f sum = Vec3f::Zero();
        int used = 0;
        binSensitivity.clear();
        for (int s = 0; s < o.samplesPerBin; ++s) {
          const float cosT = 1.0f - (i + rng.uniform()) / o.thetaBins;
          const float phi = 2 * kPi * (j + rng.uniform()) / o.phiBins;
          const Vec3f l = localDir(cosT, phi);
          const Vec3f dir = (l.x() * T + l.y() * B + l.z() * N).normalized();
          if (dir.dot(Ng) <= 0) {  // below the geometric surface: nothing arrives
            ++used;
            continue;
          }
          sampleSensitivity.clear();
          const Vec3f L = tracer.radiance(org, dir, afterFirst, rng, nullptr, firstPdf, sens);
          if (L.allFinite()) {
            sum += L;
            ++used;
            // irradiance: this sample's radiance times its cosine, the bin's mean times dOmega
            if (sens) binSensitivity.addScaled(sampleSensitivity, l.z());
          }
        }
        if (sens && used) pointSensitivity[k].addScaled(binSensitivity, binOmega / used);
        g.radiance[(k * o.thetaBins + i) * o.phiBins + j] =
            (used ? Vec3f(sum / used) : Vec3f::Zero()) +
            (direct.empty() ? Vec3f::Zero() : direct[static_cast<size_t>(i) * o.phiBins + j]);
      }
  });
  if (o.albedoSensitivity) {
    g.sensitivityStart.assign(1, 0);
    for (const AlbedoSensitivity& s : pointSensitivity) {
      g.sensitivityPart.insert(g.sensitivityPart.end(), s.part.begin(), s.part.end());
      g.sensitivityValue.insert(g.sensitivityValue.end(), s.value.begin(), s.value.end());
      g.sensitivityStart.push_back(static_cast<int>(g.sensitivityPart.size()));
    }
  }
  return g;
}

void shBasis(const Vec3f& d, int bands, float* Y) {
  // real SH up to l = 4 (bands <= 5), standard normalisation
  const float x = d.x(), y = d.y(), z = d.z();
  Y[0] = 0.282095f;
  if (bands > 1) {
    Y[1] = 0.488603f * y;
    Y[2] = 0.488603f * z;
    Y[3] = 0.488603f * x;
  }
  if (bands > 2) {
    Y[4] = 1.092548f * x * y;
    Y[5] = 1.092548f * y * z;
    Y[6] = 0.315392f * (3 * z * z - 1);
    Y[7] = 1.092548f * x * z;
    Y[8] = 0.546274f * (x * x - y * y);
  }
  if (bands > 3) {
    Y[9] = 0.590044f * y * (3 * x * x - y * y);
    Y[10] = 2.890611f * x * y * z;
    Y[11] = 0.457046f * y * (5 * z * z - 1);
    Y[12] = 0.373176f * z * (5 * z * z - 3);
    Y[13] = 0.457046f * x * (5 * z * z - 1);
    Y[14] = 1.445306f * z * (x * x - y * y);
    Y[15] = 0.590044f * x * (x * x - 3 * y * y);
  }
  if (bands > 4) {
    const float x2 = x * x, y2 = y * y, z2 = z * z;
    Y[16] = 2.503343f * x * y * (x2 - y2);
    Y[17] = 1.770131f * y * z * (3 * x2 - y2);
    Y[18] = 0.946175f * x * y * (7 * z2 - 1);
    Y[19] = 0.669047f * y * z * (7 * z2 - 3);
    Y[20] = 0.105786f * (35 * z2 * z2 - 30 * z2 + 3);
    Y[21] = 0.669047f * x * z * (7 * z2 - 3);
    Y[22] = 0.473087f * (x2 - y2) * (7 * z2 - 1);
    Y[23] = 1.770131f * x * z * (x2 - 3 * y2);
    Y[24] = 0.625836f * (x2 * x2 - 6 * x2 * y2 + y2 * y2);
  }
}

Vec3f ShRadiance::eval(const Vec3f& d) const {
  float Y[25];
  shBasis(d, bands, Y);
  Vec3f s = Vec3f::Zero();
  for (int k = 0; k < bands * bands; ++k) s += coeffs[k] * Y[k];
  return s.cwiseMax(0.0f);
}

ShRadiance projectToSh(const IncidentLightGrid& g, int gx, int gy, int bands) {
  PS_Check(bands >= 1 && bands <= 5, "SH bands in [1, 5]");
  ShRadiance sh;
  sh.bands = bands;
  sh.coeffs.assign(bands * bands, Vec3f::Zero());
  float Y[25];
  const int sub = 4;
  const float dOmega = g.binSolidAngle() / (sub * sub);
  for (int i = 0; i < g.thetaBins; ++i)
    for (int j = 0; j < g.phiBins; ++j) {
      const Vec3f& L = g.at(gx, gy, i, j);
      for (int a = 0; a < sub; ++a)
        for (int b = 0; b < sub; ++b) {
          const Vec3f d = localDir(1.0f - (i + (a + 0.5f) / sub) / g.thetaBins,
                                   2 * kPi * (j + (b + 0.5f) / sub) / g.phiBins);
          shBasis(d, bands, Y);
          for (int k = 0; k < bands * bands; ++k) sh.coeffs[k] += L * (Y[k] * dOmega);
        }
    }
  return sh;
}

}  // namespace ps
