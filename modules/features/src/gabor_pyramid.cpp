#include "gabor_pyramid.hpp"

#include "photoscene/core/error.hpp"
#include "photoscene/core/image.hpp"
#include "photoscene/core/parallel.hpp"
#include "photoscene/core/color.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

namespace ps::features_detail {
namespace {

constexpr double kLumR = kLuminanceWeights[0], kLumG = kLuminanceWeights[1],
                 kLumB = kLuminanceWeights[2];
constexpr int kBorder = cv::BORDER_CONSTANT | cv::BORDER_ISOLATED;
// Responses near the mask's edge are amplified by at most 1 / sqrt(this).
constexpr double kMinEnergyCoverage = 0.1;

// Correlation with zero padding (the adjoint is correlation with the flipped kernel).
void correlate(const cv::Mat& src, cv::Mat& dst, const cv::Mat& kernel) {
  cv::filter2D(src, dst, CV_32F, kernel, cv::Point(-1, -1), 0.0, kBorder);
}

void blur5(const cv::Mat& src, cv::Mat& dst, const GaborBank& bank) {
  cv::sepFilter2D(src, dst, CV_32F, bank.blurH, bank.blurV, cv::Point(-1, -1), 0.0, kBorder);
}

}  // namespace

cv::Mat downsample(const cv::Mat& src, const GaborBank& bank) {
  cv::Mat blurred;
  blur5(src, blurred, bank);
  cv::Mat dst((src.rows + 1) / 2, (src.cols + 1) / 2, CV_32F);
  for (int y = 0; y < dst.rows; ++y) {
    const float* s = blurred.ptr<float>(2 * y);
    float* d = dst.ptr<float>(y);
    for (int x = 0; x < dst.cols; ++x) d[x] = s[2 * x];
  }
  return dst;
}

// Adjoint of downsample: zero-insert to `size`, then the (symmetric) blur.
cv::Mat downsampleAdjoint(const cv::Mat& g, cv::Size size, const GaborBank& bank) {
  cv::Mat up = cv::Mat::zeros(size, CV_32F);
  for (int y = 0; y < g.rows; ++y) {
    const float* s = g.ptr<float>(y);
    float* d = up.ptr<float>(2 * y);
    for (int x = 0; x < g.cols; ++x) d[2 * x] = s[x];
  }
  cv::Mat out;
  blur5(up, out, bank);
  return out;
}

namespace {

double sumOf(const cv::Mat& m) {
  return cv::sum(m)[0];
}

}  // namespace

void checkDescriptorInputs(const cv::Mat& image, const cv::Mat& mask) {
  checkImage(image, CV_32FC3, "texture descriptor image");
  checkImage(mask, CV_8UC1, image.size(), "texture descriptor mask");
  PS_Check(allFinite(image), "texture descriptor image has NaN or Inf values");
}

GaborBank makeGaborBank(const TextureDescriptorOptions& o) {
  GaborBank bank;
  const int radius = std::max(1, static_cast<int>(std::ceil(o.kernelRadiusSigmas * o.sigma)));
  const int n = 2 * radius + 1;
  std::vector<double> env(n);
  double envSum = 0.0;
  for (int i = 0; i < n; ++i) {
    const double u = i - radius;
    env[i] = std::exp(-u * u / (2.0 * o.sigma * o.sigma));
    envSum += env[i];
  }
  bank.envH.create(1, n, CV_32F);
  for (int i = 0; i < n; ++i) bank.envH.at<float>(0, i) = static_cast<float>(env[i] / envSum);
  bank.envV = bank.envH.t();
  double env2Sum = 0.0;
  for (int i = 0; i < n; ++i) env2Sum += env[i] * env[i];
  bank.env2H.create(1, n, CV_32F);
  for (int i = 0; i < n; ++i)
    bank.env2H.at<float>(0, i) = static_cast<float>(env[i] * env[i] / env2Sum);
  bank.env2V = bank.env2H.t();
  // Each 1-D factor sums to sqrt(2): the 2-D envelope sums to 2, so a unit-amplitude grating at
  // the center frequency gives |r| of about 1.
  const double scale = std::sqrt(2.0) / envSum;
  const double omega = 2.0 * CV_PI * o.centerFrequency;
  for (int k = 0; k < o.numOrientations; ++k) {
    const double theta = CV_PI * k / o.numOrientations;
    const double c = std::cos(theta), s = std::sin(theta);
    GaborBank::Orientation ori;
    ori.hr.create(1, n, CV_32F);
    ori.hi.create(1, n, CV_32F);
    ori.vr.create(n, 1, CV_32F);
    ori.vi.create(n, 1, CV_32F);
    double maxHi = 0.0, maxVi = 0.0;
    for (int i = 0; i < n; ++i) {
      const double u = i - radius;
      const double e = env[i] * scale;
      const float hi = static_cast<float>(e * std::sin(omega * u * c));
      const float vi = static_cast<float>(e * std::sin(omega * u * s));
      ori.hr.at<float>(0, i) = static_cast<float>(e * std::cos(omega * u * c));
      ori.hi.at<float>(0, i) = hi;
      ori.vr.at<float>(i, 0) = static_cast<float>(e * std::cos(omega * u * s));
      ori.vi.at<float>(i, 0) = vi;
      maxHi = std::max(maxHi, std::abs(static_cast<double>(hi)));
      maxVi = std::max(maxVi, std::abs(static_cast<double>(vi)));
    }
    double sumHr = 0.0, sumVr = 0.0;
    for (int i = 0; i < n; ++i) {
      sumHr += ori.hr.at<float>(0, i);
      sumVr += ori.vr.at<float>(i, 0);
    }
    ori.dc = static_cast<float>(sumHr * sumVr);
    ori.hiZero = maxHi < 1e-7;
    ori.viZero = maxVi < 1e-7;
    if (ori.hiZero) ori.hi.setTo(0);
    if (ori.viZero) ori.vi.setTo(0);
    cv::flip(ori.hr, ori.hrF, 1);
    cv::flip(ori.hi, ori.hiF, 1);
    cv::flip(ori.vr, ori.vrF, 0);
    cv::flip(ori.vi, ori.viF, 0);
    bank.orient.push_back(ori);
  }
  bank.blurH = (cv::Mat_<float>(1, 5) << 1.f / 16, 4.f / 16, 6.f / 16, 4.f / 16, 1.f / 16);
  bank.blurV = bank.blurH.t();
  return bank;
}

MaskPyramid makeMaskPyramid(const cv::Mat& mask, const TextureDescriptorOptions& o,
                            const GaborBank& bank) {
  MaskPyramid p;
  const cv::Rect box = cv::boundingRect(mask);
  p.count = cv::countNonZero(mask);
  PS_Check(p.count > 0 && box.area() > 0,
           "texture descriptor: the mask is empty (a region without pixels has no texture)");
  // Align the crop origin to the coarsest level's grid, so the result does not depend on how much
  // of the image is passed in.
  const int align = 1 << (o.numScales - 1);
  const int x0 = box.x / align * align, y0 = box.y / align * align;
  p.crop = cv::Rect(x0, y0, box.x + box.width - x0, box.y + box.height - y0);
  cv::Mat m8 = mask(p.crop);
  p.mask0.create(p.crop.size(), CV_32F);
  for (int y = 0; y < p.crop.height; ++y) {
    const uint8_t* s = m8.ptr<uint8_t>(y);
    float* d = p.mask0.ptr<float>(y);
    for (int x = 0; x < p.crop.width; ++x) d[x] = s[x] ? 1.0f : 0.0f;
  }
  cv::Mat coverage = p.mask0;
  for (int s = 0; s < o.numScales; ++s) {
    if (s > 0) coverage = downsample(coverage, bank);
    cv::Mat inside;
    cv::sepFilter2D(coverage, inside, CV_32F, bank.envH, bank.envV, cv::Point(-1, -1), 0.0,
                    kBorder);
    cv::Mat w(coverage.size(), CV_32F);
    for (int y = 0; y < w.rows; ++y) {
      const float* m = coverage.ptr<float>(y);
      const float* c = inside.ptr<float>(y);
      float* d = w.ptr<float>(y);
      for (int x = 0; x < w.cols; ++x) {
        const double cover = std::clamp(static_cast<double>(c[x]), 0.0, 1.0);
        const double mv = std::max(0.0, static_cast<double>(m[x]));
        d[x] =
            static_cast<float>(mv * (o.boundaryPower > 0 ? std::pow(cover, o.boundaryPower) : 1.0));
      }
    }
    const double total = sumOf(w);
    if (total > 0 && std::isfinite(total)) {
      w *= 1.0 / total;
    } else {
      w.setTo(0);
    }
    p.weight.push_back(w);
    // Energy coverage: the share of the filter's energy (|g|^2) that falls on the region
    // (coverage squared: the pyramid attenuates amplitudes by the coverage).
    // Undo the pyramid blurs' attenuation at this level's center frequency (unit gain per band).
    double pyramidGain = 1.0;
    for (int j = 0; j < s; ++j) {
      const double h =
          0.5 * (1.0 + std::cos(2.0 * CV_PI * o.centerFrequency * std::ldexp(1.0, j - s)));
      pyramidGain *= h * h;
    }
    cv::Mat cov2 = coverage.mul(coverage), c2, gain(coverage.size(), CV_32F);
    cv::sepFilter2D(cov2, c2, CV_32F, bank.env2H, bank.env2V, cv::Point(-1, -1), 0.0, kBorder);
    for (int y = 0; y < gain.rows; ++y) {
      const float* c = c2.ptr<float>(y);
      float* g = gain.ptr<float>(y);
      for (int x = 0; x < gain.cols; ++x)
        g[x] = static_cast<float>(
            1.0 / (pyramidGain * std::sqrt(std::max<double>(c[x], kMinEnergyCoverage))));
    }
    p.gain.push_back(gain);
    p.weightSum.push_back(total * std::pow(4.0, s));
  }
  return p;
}

void forwardDescriptor(const cv::Mat& image, const MaskPyramid& p, const GaborBank& bank,
                       const TextureDescriptorOptions& o, ForwardState& st, bool keep) {
  const int S = o.numScales, K = o.numOrientations;
  st.values.assign(descriptorLength(o), 0.0);
  image(p.crop).copyTo(st.rgb);
  const int W = p.crop.width, H = p.crop.height;
  const double eps2 = o.epsilon * o.epsilon;

  // Color statistics and the centered luminance.
  double sum[3] = {0, 0, 0}, sum2[3] = {0, 0, 0}, lumSum = 0.0;
  for (int y = 0; y < H; ++y) {
    const cv::Vec3f* c = st.rgb.ptr<cv::Vec3f>(y);
    const float* m = p.mask0.ptr<float>(y);
    for (int x = 0; x < W; ++x) {
      if (m[x] == 0.0f) continue;
      for (int ch = 0; ch < 3; ++ch) {
        sum[ch] += c[x][ch];
        sum2[ch] += static_cast<double>(c[x][ch]) * c[x][ch];
      }
      lumSum += kLumR * c[x][0] + kLumG * c[x][1] + kLumB * c[x][2];
    }
  }
  const double n = p.count;
  for (int ch = 0; ch < 3; ++ch) {
    const double mean = sum[ch] / n;
    const double var = std::max(0.0, sum2[ch] / n - mean * mean);
    st.values[ch] = mean;
    st.values[3 + ch] = std::sqrt(var + eps2);
  }
  const double mu = lumSum / n;
  st.z.assign(S, cv::Mat());
  st.z[0].create(H, W, CV_32F);
  for (int y = 0; y < H; ++y) {
    const cv::Vec3f* c = st.rgb.ptr<cv::Vec3f>(y);
    const float* m = p.mask0.ptr<float>(y);
    float* z = st.z[0].ptr<float>(y);
    for (int x = 0; x < W; ++x) {
      z[x] = m[x] == 0.0f
                 ? 0.0f
                 : static_cast<float>(kLumR * c[x][0] + kLumG * c[x][1] + kLumB * c[x][2] - mu);
    }
  }
  for (int s = 1; s < S; ++s) st.z[s] = downsample(st.z[s - 1], bank);

  // The envelope-filtered levels, for the DC correction of the real parts.
  std::vector<cv::Mat> env(S);
  for (int s = 0; s < S; ++s)
    cv::sepFilter2D(st.z[s], env[s], CV_32F, bank.envH, bank.envV, cv::Point(-1, -1), 0.0, kBorder);
  st.a.assign(S * K, cv::Mat());
  st.b.assign(S * K, cv::Mat());
  st.mag.assign(S * K, cv::Mat());
  parallelFor(0, S * K, [&](int64_t band) {
    const int s = static_cast<int>(band / K), k = static_cast<int>(band % K);
    const GaborBank::Orientation& ori = bank.orient[k];
    const cv::Mat& z = st.z[s];
    cv::Mat tR, tI, a, b, tmp;
    correlate(z, tR, ori.hr);
    if (!ori.hiZero) correlate(z, tI, ori.hi);
    correlate(tR, a, ori.vr);
    if (!ori.viZero) {
      correlate(tR, b, ori.vi);
    } else {
      b = cv::Mat::zeros(z.size(), CV_32F);
    }
    if (!ori.hiZero) {
      if (!ori.viZero) {
        correlate(tI, tmp, ori.vi);
        a -= tmp;
      }
      correlate(tI, tmp, ori.vr);
      b += tmp;
    }
    if (ori.dc != 0.0f) cv::scaleAdd(env[s], -ori.dc, a, a);
    a = a.mul(p.gain[s]);
    b = b.mul(p.gain[s]);
    cv::Mat mag(z.size(), CV_32F);
    const cv::Mat& w = p.weight[s];
    double sa = 0, sa2 = 0, sm = 0, sm2 = 0;
    for (int y = 0; y < z.rows; ++y) {
      const float* pa = a.ptr<float>(y);
      const float* pb = b.ptr<float>(y);
      const float* pw = w.ptr<float>(y);
      float* pm = mag.ptr<float>(y);
      for (int x = 0; x < z.cols; ++x) {
        const double av = pa[x], bv = pb[x];
        const double mv = std::sqrt(av * av + bv * bv + eps2);
        pm[x] = static_cast<float>(mv);
        const double wv = pw[x];
        if (wv == 0.0) continue;
        sa += wv * av;
        sa2 += wv * av * av;
        sm += wv * mv;
        sm2 += wv * mv * mv;
      }
    }
    const int base = bandIndex(o, s, k);
    st.values[base + kBandMeanRe] = sa;
    st.values[base + kBandStdRe] = std::sqrt(std::max(0.0, sa2 - sa * sa) + eps2);
    st.values[base + kBandMeanMag] = sm;
    st.values[base + kBandStdMag] = std::sqrt(std::max(0.0, sm2 - sm * sm) + eps2);
    if (keep) {
      st.a[band] = a;
      st.b[band] = b;
      st.mag[band] = mag;
    }
  });
}

void backwardDescriptor(const MaskPyramid& p, const GaborBank& bank,
                        const TextureDescriptorOptions& o, const ForwardState& st,
                        const std::vector<double>& g, cv::Mat& gradCrop,
                        const ExtraGradients* extra) {
  const int S = o.numScales, K = o.numOrientations;
  const int W = p.crop.width, H = p.crop.height;
  PS_CheckEQ(static_cast<int>(g.size()), descriptorLength(o), "gradient length");
  PS_Check(static_cast<int>(st.a.size()) == S * K && !st.a.empty() && !st.a[0].empty(),
           "backward needs a forward pass that kept its intermediates");

  // Per band: d out / d z_s, into its own buffer (summed in a fixed order below).
  std::vector<cv::Mat> gz(S * K);
  parallelFor(0, S * K, [&](int64_t band) {
    const int s = static_cast<int>(band / K), k = static_cast<int>(band % K);
    const int base = bandIndex(o, s, k);
    const double g0 = g[base + kBandMeanRe], g1 = g[base + kBandStdRe];
    const double g2 = g[base + kBandMeanMag], g3 = g[base + kBandStdMag];
    const cv::Mat* extraMag =
        extra && static_cast<int>(extra->mag.size()) > band && !extra->mag[band].empty()
            ? &extra->mag[band]
            : nullptr;
    if (g0 == 0.0 && g1 == 0.0 && g2 == 0.0 && g3 == 0.0 && !extraMag) return;
    const double meanA = st.values[base + kBandMeanRe], stdA = st.values[base + kBandStdRe];
    const double meanM = st.values[base + kBandMeanMag], stdM = st.values[base + kBandStdMag];
    const cv::Mat& a = st.a[band];
    const cv::Mat& b = st.b[band];
    const cv::Mat& mag = st.mag[band];
    const cv::Mat& w = p.weight[s];
    cv::Mat ga(a.size(), CV_32F), gb(a.size(), CV_32F);
    for (int y = 0; y < a.rows; ++y) {
      const float* pa = a.ptr<float>(y);
      const float* pb = b.ptr<float>(y);
      const float* pm = mag.ptr<float>(y);
      const float* pw = w.ptr<float>(y);
      float* qa = ga.ptr<float>(y);
      float* qb = gb.ptr<float>(y);
      const float* pe = extraMag ? extraMag->ptr<float>(y) : nullptr;
      for (int x = 0; x < a.cols; ++x) {
        const double wv = pw[x];
        const double ge = pe ? pe[x] : 0.0;
        if (wv == 0.0 && ge == 0.0) {
          qa[x] = qb[x] = 0.0f;
          continue;
        }
        const double gm = wv * (g2 + g3 * (pm[x] - meanM) / stdM) + ge;
        const double inv = 1.0 / pm[x];
        qa[x] = static_cast<float>(wv * (g0 + g1 * (pa[x] - meanA) / stdA) + gm * pa[x] * inv);
        qb[x] = static_cast<float>(gm * pb[x] * inv);
      }
    }
    ga = ga.mul(p.gain[s]);
    gb = gb.mul(p.gain[s]);
    const GaborBank::Orientation& ori = bank.orient[k];
    // a = Vr tR - Vi tI, b = Vi tR + Vr tI  =>  gtR = Vr' ga + Vi' gb, gtI = -Vi' ga + Vr' gb
    cv::Mat gtR, gtI, tmp;
    correlate(ga, gtR, ori.vrF);
    if (!ori.viZero) {
      correlate(gb, tmp, ori.viF);
      gtR += tmp;
    }
    cv::Mat out;
    correlate(gtR, out, ori.hrF);
    if (!ori.hiZero) {
      correlate(gb, gtI, ori.vrF);
      if (!ori.viZero) {
        correlate(ga, tmp, ori.viF);
        gtI -= tmp;
      }
      correlate(gtI, tmp, ori.hiF);
      out += tmp;
    }
    if (ori.dc != 0.0f) {  // a -= dc * env(z): the envelope is symmetric, its own adjoint
      cv::sepFilter2D(ga, tmp, CV_32F, bank.envH, bank.envV, cv::Point(-1, -1), 0.0, kBorder);
      cv::scaleAdd(tmp, -ori.dc, out, out);
    }
    gz[band] = out;
  });

  // Down the pyramid's adjoint, coarse to fine.
  cv::Mat carry;
  for (int s = S - 1; s >= 0; --s) {
    cv::Mat acc = cv::Mat::zeros(st.z[s].size(), CV_32F);
    if (!carry.empty()) acc += downsampleAdjoint(carry, st.z[s].size(), bank);
    for (int k = 0; k < K; ++k) {
      if (!gz[s * K + k].empty()) acc += gz[s * K + k];
    }
    if (extra && static_cast<int>(extra->z.size()) > s && !extra->z[s].empty()) acc += extra->z[s];
    carry = acc;
  }
  // carry = d out / d z0; z0 = M (L - mu), mu = sum(M L) / n.
  const double n = p.count;
  double gSum = 0.0;
  for (int y = 0; y < H; ++y) {
    const float* m = p.mask0.ptr<float>(y);
    const float* gzr = carry.ptr<float>(y);
    for (int x = 0; x < W; ++x) gSum += m[x] * gzr[x];
  }
  const double gMu = gSum / n;
  double gMean[3], gStdOverStd[3];
  for (int ch = 0; ch < 3; ++ch) {
    gMean[ch] = g[ch] / n;
    gStdOverStd[ch] = g[3 + ch] / (n * st.values[3 + ch]);
  }
  gradCrop.create(H, W, CV_32FC3);
  const double lum[3] = {kLumR, kLumG, kLumB};
  for (int y = 0; y < H; ++y) {
    const float* m = p.mask0.ptr<float>(y);
    const float* gzr = carry.ptr<float>(y);
    const cv::Vec3f* c = st.rgb.ptr<cv::Vec3f>(y);
    cv::Vec3f* out = gradCrop.ptr<cv::Vec3f>(y);
    for (int x = 0; x < W; ++x) {
      if (m[x] == 0.0f) {
        out[x] = cv::Vec3f(0, 0, 0);
        continue;
      }
      const double gL = gzr[x] - gMu;
      for (int ch = 0; ch < 3; ++ch) {
        out[x][ch] = static_cast<float>(lum[ch] * gL + gMean[ch] +
                                        gStdOverStd[ch] * (c[x][ch] - st.values[ch]));
      }
      if (extra && !extra->rgb.empty()) out[x] += extra->rgb.at<cv::Vec3f>(y, x);
    }
  }
}

TextureDescriptor toDescriptor(const ForwardState& st, const MaskPyramid& p,
                               const TextureDescriptorOptions& o) {
  TextureDescriptor d;
  d.values.assign(st.values.begin(), st.values.end());
  d.numScales = o.numScales;
  d.numOrientations = o.numOrientations;
  d.maskPixels = p.count;
  for (double w : p.weightSum) d.scaleSupport.push_back(static_cast<float>(w));
  return d;
}

}  // namespace ps::features_detail
