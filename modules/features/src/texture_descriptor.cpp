#include "photoscene/features/texture_descriptor.hpp"

#include "gabor_pyramid.hpp"
#include "ps_statistics.hpp"
#include "photoscene/core/error.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace ps {

using namespace features_detail;

bool TextureDescriptorOptions::IsValid(std::string* error) const {
  std::ostringstream os;
  if (numScales < 1 || numScales > 12)
    os << "numScales must be in [1, 12], got " << numScales;
  else if (numOrientations < 1 || numOrientations > 32)
    os << "numOrientations must be in [1, 32], got " << numOrientations;
  else if (!(centerFrequency > 0.0 && centerFrequency < 0.5))
    os << "centerFrequency must be in (0, 0.5) cycles per pixel, got " << centerFrequency;
  else if (!(sigma >= 0.5 && sigma <= 16.0))
    os << "sigma must be in [0.5, 16], got " << sigma;
  else if (!(kernelRadiusSigmas >= 1.0 && kernelRadiusSigmas <= 5.0))
    os << "kernelRadiusSigmas must be in [1, 5], got " << kernelRadiusSigmas;
  else if (!(boundaryPower >= 0.0 && boundaryPower <= 16.0))
    os << "boundaryPower must be in [0, 16], got " << boundaryPower;
  else if (!(epsilon > 0.0 && epsilon < 1.0))
    os << "epsilon must be in (0, 1), got " << epsilon;
  const std::string msg = os.str();
  if (error) *error = msg;
  return msg.empty();
}

bool TextureKeyOptions::IsValid(std::string* error) const {
  if (!descriptor.IsValid(error)) return false;
  std::string msg;
  if (!(colorWeight >= 0 && contrastWeight >= 0 && anisotropyWeight >= 0 && psWeight >= 0))
    msg = "key group weights must be >= 0";
  else if (!(logFloor > 0.0f))
    msg = "logFloor must be > 0";
  if (error) *error = msg;
  return msg.empty();
}

int descriptorLength(const TextureDescriptorOptions& o) {
  return kTextureColorEntries + 4 * o.numScales * o.numOrientations;
}

int bandIndex(const TextureDescriptorOptions& o, int scale, int orientation) {
  return kTextureColorEntries + 4 * (scale * o.numOrientations + orientation);
}

int keyPsLength(const TextureDescriptorOptions& o) {
  const int S = o.numScales, K = o.numOrientations;
  return 4 * S + 2 * S + S * (K / 2) + (S - 1) * (K / 2 + 1) + 5;
}

int keyLength(const TextureKeyOptions& o) {
  const int S = o.descriptor.numScales, K = o.descriptor.numOrientations;
  return 6 + 3 * S + S * (K / 2) + (o.psWeight > 0 ? keyPsLength(o.descriptor) : 0);
}

namespace {

// The pooled joint statistics of the key (computeTextureKey's documentation), unweighted, in
// groups: sizes written to groupSizes.
std::vector<double> pooledPs(const std::vector<double>& v, const TextureDescriptorOptions& o,
                             const TexturePsOptions& po, double logFloor,
                             std::vector<int>& groupSizes) {
  const int S = o.numScales, K = o.numOrientations;
  const TexturePsLayout L = texturePsLayout(o, po);
  std::vector<double> out;
  auto rings = [&](int offset, int radius, const std::vector<double>& edges) {
    const std::vector<cv::Point> lags = psLags(radius);
    std::vector<double> sum(edges.size() - 1, 0.0), n(edges.size() - 1, 0.0);
    for (size_t i = 0; i < lags.size(); ++i) {
      const double r = std::hypot(lags[i].x, lags[i].y);
      for (size_t b = 0; b + 1 < edges.size(); ++b)
        if (r >= edges[b] && r < edges[b + 1]) sum[b] += v[offset + i], n[b] += 1;
    }
    for (size_t b = 0; b < sum.size(); ++b) sum[b] = n[b] > 0 ? sum[b] / n[b] : 0.0;
    return sum;
  };
  const std::vector<double> lowEdges = {1.0, 1.6, 2.4, 3.3, 4.3}, magEdges = {1.0, 1.6, 2.9};
  const int nL = texturePsLagCount(po.lowpassRadius), nM = texturePsLagCount(po.magnitudeRadius);
  for (int s = 0; s < S; ++s)
    for (double r : rings(L.autoLowpass + s * nL, po.lowpassRadius, lowEdges)) out.push_back(r);
  groupSizes.push_back(4 * S);
  for (int s = 0; s < S; ++s) {
    std::vector<double> acc(2, 0.0);
    for (int k = 0; k < K; ++k) {
      const std::vector<double> r =
          rings(L.autoMagnitude + (s * K + k) * nM, po.magnitudeRadius, magEdges);
      for (int b = 0; b < 2; ++b) acc[b] += r[b] / K;
    }
    out.insert(out.end(), acc.begin(), acc.end());
  }
  groupSizes.push_back(2 * S);
  auto circularDistance = [&](int k, int l) {
    const int d = std::abs(k - l) % K;
    return std::min(d, K - d);
  };
  int idx = L.crossOrientation;
  for (int s = 0; s < S; ++s) {
    std::vector<double> sum(K / 2 + 1, 0.0), n(K / 2 + 1, 0.0);
    for (int k = 0; k < K; ++k)
      for (int l = k + 1; l < K; ++l) {
        const int h = circularDistance(k, l);
        sum[h] += v[idx++];
        n[h] += 1;
      }
    for (int h = 1; h <= K / 2; ++h) out.push_back(n[h] > 0 ? sum[h] / n[h] : 0.0);
  }
  groupSizes.push_back(S * (K / 2));
  for (int s = 0; s + 1 < S; ++s) {
    std::vector<double> sum(K / 2 + 1, 0.0), n(K / 2 + 1, 0.0);
    for (int k = 0; k < K; ++k)
      for (int l = 0; l < K; ++l) {
        const int h = circularDistance(k, l);
        sum[h] += v[L.crossScale + (s * K + k) * K + l];
        n[h] += 1;
      }
    for (int h = 0; h <= K / 2; ++h) out.push_back(n[h] > 0 ? sum[h] / n[h] : 0.0);
  }
  groupSizes.push_back((S - 1) * (K / 2 + 1));
  for (int t = 0; t < 3; ++t) out.push_back(v[L.color + 6 + t]);
  const double sd3 = v[L.color + 5];
  out.push_back(std::log((v[L.color + 3] + logFloor) / (sd3 + logFloor)));
  out.push_back(std::log((v[L.color + 4] + logFloor) / (sd3 + logFloor)));
  groupSizes.push_back(5);
  return out;
}

}  // namespace

static void checkOptions(const TextureDescriptorOptions& o) {
  std::string err;
  PS_Check(o.IsValid(&err), "invalid TextureDescriptorOptions: " << err);
}

TextureDescriptor computeTextureDescriptor(const cv::Mat& image, const cv::Mat& mask,
                                           const TextureDescriptorOptions& options) {
  checkOptions(options);
  checkDescriptorInputs(image, mask);
  const GaborBank bank = makeGaborBank(options);
  const MaskPyramid pyramid = makeMaskPyramid(mask, options, bank);
  ForwardState state;
  forwardDescriptor(image, pyramid, bank, options, state, false);
  return toDescriptor(state, pyramid, options);
}

std::vector<float> computeTextureKey(const cv::Mat& image, const cv::Mat& mask,
                                     const TextureKeyOptions& options) {
  std::string err;
  PS_Check(options.IsValid(&err), "invalid TextureKeyOptions: " << err);
  checkDescriptorInputs(image, mask);
  const TextureDescriptorOptions& o = options.descriptor;
  const GaborBank bank = makeGaborBank(o);
  MaskPyramid pyramid = makeMaskPyramid(mask, o, bank);
  const cv::Rect crop = pyramid.crop;

  // Per-channel levels over the mask (the paper matches medians).
  std::vector<float> vals[3];
  for (auto& v : vals) v.reserve(pyramid.count);
  for (int y = 0; y < crop.height; ++y) {
    const cv::Vec3f* c = image.ptr<cv::Vec3f>(crop.y + y) + crop.x;
    const float* m = pyramid.mask0.ptr<float>(y);
    for (int x = 0; x < crop.width; ++x) {
      if (m[x] == 0.0f) continue;
      for (int ch = 0; ch < 3; ++ch) vals[ch].push_back(c[x][ch]);
    }
  }
  // Interquartile mean per channel: as robust to highlights as the median, and continuous for
  // two-tone textures (a checker's median jumps between its two tones).
  double level[3];
  for (int ch = 0; ch < 3; ++ch) {
    std::vector<float>& v = vals[ch];
    const size_t lo = v.size() / 4, hi = std::max(lo + 1, v.size() - v.size() / 4);
    std::nth_element(v.begin(), v.begin() + lo, v.end());
    std::nth_element(v.begin() + lo, v.begin() + (hi - 1), v.end());
    double sum = 0.0;
    for (size_t i = lo; i < hi; ++i) sum += v[i];
    level[ch] = std::max(0.0, sum / static_cast<double>(hi - lo));
  }
  const double maxLevel = std::max({level[0], level[1], level[2]});
  cv::Mat normalized(crop.size(), CV_32FC3);
  double scale[3];
  for (int ch = 0; ch < 3; ++ch) scale[ch] = 1.0 / (level[ch] + 1e-6 * maxLevel + 1e-12);
  for (int y = 0; y < crop.height; ++y) {
    const cv::Vec3f* c = image.ptr<cv::Vec3f>(crop.y + y) + crop.x;
    cv::Vec3f* d = normalized.ptr<cv::Vec3f>(y);
    for (int x = 0; x < crop.width; ++x) {
      for (int ch = 0; ch < 3; ++ch) d[x][ch] = static_cast<float>(c[x][ch] * scale[ch]);
    }
  }
  pyramid.crop = cv::Rect(0, 0, crop.width, crop.height);
  ForwardState st;
  forwardDescriptor(normalized, pyramid, bank, o, st, options.psWeight > 0);
  const std::vector<double>& D = st.values;

  // Inter-channel correlations of the normalized region.
  double mean[3] = {D[0], D[1], D[2]};
  double cov[3] = {0, 0, 0};  // RG, GB, BR
  for (int y = 0; y < crop.height; ++y) {
    const cv::Vec3f* c = normalized.ptr<cv::Vec3f>(y);
    const float* m = pyramid.mask0.ptr<float>(y);
    for (int x = 0; x < crop.width; ++x) {
      if (m[x] == 0.0f) continue;
      const double r = c[x][0] - mean[0], g = c[x][1] - mean[1], b = c[x][2] - mean[2];
      cov[0] += r * g;
      cov[1] += g * b;
      cov[2] += b * r;
    }
  }
  const int S = o.numScales, K = o.numOrientations;
  std::vector<double> key;
  key.reserve(keyLength(options));
  const double floor = options.logFloor;
  double var[3];
  for (int ch = 0; ch < 3; ++ch) {
    const double sd = D[3 + ch];
    var[ch] = std::max(0.0, sd * sd - o.epsilon * o.epsilon);
    key.push_back(std::log(sd + floor));
  }
  const int pairs[3][2] = {{0, 1}, {1, 2}, {2, 0}};
  for (int i = 0; i < 3; ++i) {
    const double va = var[pairs[i][0]], vb = var[pairs[i][1]];
    const double denom = std::sqrt(va * vb);
    key.push_back(denom > 1e-12 ? std::clamp(cov[i] / pyramid.count / denom, -1.0, 1.0) : 0.0);
  }
  for (int s = 0; s < S; ++s) {
    double mm = 0, sm = 0, sr = 0;
    for (int k = 0; k < K; ++k) {
      const int b = bandIndex(o, s, k);
      mm += D[b + kBandMeanMag];
      sm += D[b + kBandStdMag];
      sr += D[b + kBandStdRe];
    }
    key.push_back(std::log(mm / K + floor));
    key.push_back(std::log(sm / K + floor));
    key.push_back(std::log(sr / K + floor));
  }
  for (int s = 0; s < S; ++s) {
    // The orientation profile above its isotropic floor (eps in the magnitudes), normalized.
    std::vector<double> prof(K);
    double total = 0.0;
    for (int k = 0; k < K; ++k) {
      prof[k] = std::max(0.0, D[bandIndex(o, s, k) + kBandMeanMag] - o.epsilon);
      total += prof[k];
    }
    for (int h = 1; h <= K / 2; ++h) {
      double re = 0.0, im = 0.0;
      if (total > 1e-9) {
        for (int k = 0; k < K; ++k) {
          const double ang = -2.0 * CV_PI * h * k / K;
          re += prof[k] / total * std::cos(ang);
          im += prof[k] / total * std::sin(ang);
        }
      }
      key.push_back(std::sqrt(re * re + im * im));
    }
  }
  // Group scaling.
  const int nColor = 6, nContrast = 3 * S, nAniso = S * (K / 2);
  std::vector<float> out(key.size());
  for (size_t i = 0; i < key.size(); ++i) {
    double w;
    if (static_cast<int>(i) < nColor)
      w = options.colorWeight / std::sqrt(nColor);
    else if (static_cast<int>(i) < nColor + nContrast)
      w = options.contrastWeight / std::sqrt(nContrast);
    else
      w = options.anisotropyWeight / std::sqrt(std::max(1, nAniso));
    out[i] = static_cast<float>(w * key[i]);
  }
  if (options.psWeight > 0) {
    const TexturePsOptions po;
    const PsMask psMask = makePsMask(pyramid, o, po);
    PsState ps;
    forwardPs(st, pyramid, psMask, bank, o, po, ps);
    std::vector<int> sizes;
    const std::vector<double> pooled = pooledPs(ps.values, o, po, floor, sizes);
    size_t i = 0;
    for (int n : sizes)
      for (int j = 0; j < n; ++j, ++i)
        out.push_back(static_cast<float>(options.psWeight / std::sqrt(std::max(1, n)) * pooled[i]));
  }
  PS_CheckEQ(static_cast<int>(out.size()), keyLength(options), "key length");
  return out;
}

double descriptorDistance(const std::vector<float>& a, const std::vector<float>& b) {
  PS_CheckEQ(a.size(), b.size(), "descriptors of different lengths");
  double s = 0.0;
  for (size_t i = 0; i < a.size(); ++i) {
    const double d = static_cast<double>(a[i]) - b[i];
    s += d * d;
  }
  return std::sqrt(s);
}

}  // namespace ps
