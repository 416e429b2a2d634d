#include "photoscene/features/texture_structure.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <sstream>

#include <opencv2/imgproc.hpp>

#include "photoscene/core/error.hpp"
#include "photoscene/core/color.hpp"

namespace ps {

bool TextureStructureOptions::IsValid(std::string* error) const {
  std::ostringstream os;
  if (gradientSigmas.empty() && ringEdges.size() < 2)
    os << "at least one gradient sigma or one ring";
  for (float s : gradientSigmas)
    if (!(s >= 0.5f && s <= 32.0f)) os << "gradientSigmas must be in [0.5, 32]; ";
  if (!ringEdges.empty() && !(ringEdges[0] >= 1.0f)) os << "ringEdges[0] must be >= 1; ";
  for (size_t i = 1; i < ringEdges.size(); ++i)
    if (!(ringEdges[i] > ringEdges[i - 1])) os << "ringEdges must increase; ";
  if (maxCorrelationSize < 32) os << "maxCorrelationSize must be >= 32; ";
  if (!(logFloor > 0)) os << "logFloor must be > 0; ";
  if (error) *error = os.str();
  return os.str().empty();
}

int structureKeyLength(const TextureStructureOptions& o) {
  const int rings = o.ringEdges.size() >= 2 ? static_cast<int>(o.ringEdges.size()) - 1 : 0;
  return 4 * static_cast<int>(o.gradientSigmas.size()) + 2 * rings + 6;
}

namespace {

/// Masked Gaussian blur by normalized convolution; `den` receives the blurred mask (coverage).
cv::Mat maskedBlur(const cv::Mat& values, const cv::Mat& mask01, double sigma, cv::Mat* den) {
  const int r = std::max(1, static_cast<int>(std::ceil(3 * sigma)));
  cv::Mat num, d;
  cv::GaussianBlur(values.mul(mask01), num, cv::Size(2 * r + 1, 2 * r + 1), sigma, sigma,
                   cv::BORDER_CONSTANT);
  cv::GaussianBlur(mask01, d, cv::Size(2 * r + 1, 2 * r + 1), sigma, sigma, cv::BORDER_CONSTANT);
  cv::Mat out = num / cv::max(d, 1e-6);
  if (den) *den = d;
  return out;
}

/// Bilinear sample of a CV_32FC1 map; false outside.
bool sampleAt(const cv::Mat& m, double x, double y, float* v) {
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  if (x0 < 0 || y0 < 0 || x0 + 1 >= m.cols || y0 + 1 >= m.rows) return false;
  const float fx = static_cast<float>(x - x0), fy = static_cast<float>(y - y0);
  *v = (1 - fy) * ((1 - fx) * m.at<float>(y0, x0) + fx * m.at<float>(y0, x0 + 1)) +
       fy * ((1 - fx) * m.at<float>(y0 + 1, x0) + fx * m.at<float>(y0 + 1, x0 + 1));
  return true;
}

/// Circular autocorrelation of a (zero-padded) real image, origin moved to the center.
cv::Mat autocorrelation(const cv::Mat& x, int padRows, int padCols) {
  cv::Mat padded = cv::Mat::zeros(padRows, padCols, CV_32FC1), spec, power, ac;
  x.copyTo(padded(cv::Rect(0, 0, x.cols, x.rows)));
  cv::dft(padded, spec, cv::DFT_COMPLEX_OUTPUT);
  cv::mulSpectrums(spec, spec, power, 0, true);
  cv::dft(power, ac, cv::DFT_INVERSE | cv::DFT_REAL_OUTPUT | cv::DFT_SCALE);
  return ac;
}

/// 1. Gradient direction harmonics and edge sparsity per scale. A sigma of 2^j s0 (s0 in [1, 2))
/// is applied as s0 on the field halved j times (masked area averages): the same statistics at
/// a quarter of the cost per octave.
void appendGradientStatistics(const cv::Mat& l, const cv::Mat& m01,
                              const TextureStructureOptions& options, std::vector<float>& out) {
  struct Level {
    cv::Mat l, m01;
  };
  std::vector<Level> levels{{l, m01}};
  levels.reserve(16);
  auto levelFor = [&](int j) -> const Level& {
    while (static_cast<int>(levels.size()) <= j) {
      const Level& prev = levels.back();
      if (prev.l.cols < 8 || prev.l.rows < 8) break;
      Level next;
      const cv::Size half((prev.l.cols + 1) / 2, (prev.l.rows + 1) / 2);
      cv::Mat lm;
      cv::resize(prev.l.mul(prev.m01), lm, half, 0, 0, cv::INTER_AREA);
      cv::resize(prev.m01, next.m01, half, 0, 0, cv::INTER_AREA);
      next.l = lm / cv::max(next.m01, 1e-6);
      levels.push_back(next);
    }
    return levels[std::min<size_t>(j, levels.size() - 1)];
  };
  for (float sigmaFull : options.gradientSigmas) {
    const int j = std::max(0, static_cast<int>(std::floor(std::log2(sigmaFull))));
    const Level& lev = levelFor(j);
    const double sigma = sigmaFull / std::pow(2.0, static_cast<double>(&lev - levels.data()));
    const int h = lev.l.rows, w = lev.l.cols;
    cv::Mat den;
    const cv::Mat lb = maskedBlur(lev.l, lev.m01, sigma, &den);
    std::complex<double> h2 = 0, h4 = 0, h6 = 0;
    double sw = 0, sg = 0, sg2 = 0, sc = 0;
    for (int y = 1; y + 1 < h; ++y) {
      const float* mrow = lev.m01.ptr<float>(y);
      const float* drow = den.ptr<float>(y);
      const float *r0 = lb.ptr<float>(y - 1), *r1 = lb.ptr<float>(y), *r2 = lb.ptr<float>(y + 1);
      for (int x = 1; x + 1 < w; ++x) {
        const float cov = std::min(drow[x], mrow[x]);
        if (cov < 0.5f) continue;
        const double gx = 0.5 * (r1[x + 1] - r1[x - 1]), gy = 0.5 * (r2[x] - r0[x]);
        const double g = std::sqrt(gx * gx + gy * gy);
        const double wt = cov * cov;
        sc += wt;
        sg += wt * g;
        sg2 += wt * g * g;
        if (g < 1e-9) continue;
        const std::complex<double> z(gx / g, gy / g), z2 = z * z, z4 = z2 * z2;
        h2 += wt * g * z2;
        h4 += wt * g * z4;
        h6 += wt * g * z4 * z2;
        sw += wt * g;
      }
    }
    if (sw > 1e-12) {
      out.push_back(static_cast<float>(std::abs(h2) / sw));
      out.push_back(static_cast<float>(std::abs(h4) / sw));
      out.push_back(static_cast<float>(std::abs(h6) / sw));
    } else {
      out.insert(out.end(), {0.f, 0.f, 0.f});
    }
    out.push_back(sg > 1e-12 ? static_cast<float>(std::log(sg2 * sc / (sg * sg))) : 0.f);
  }
}

/// 2. Normalized autocorrelation of log L (masked), its ring means and maxima.
void appendAutocorrelationRings(const cv::Mat& l, const cv::Mat& m01, double meanL,
                                const TextureStructureOptions& options, std::vector<float>& out) {
  const int rings =
      options.ringEdges.size() >= 2 ? static_cast<int>(options.ringEdges.size()) - 1 : 0;
  if (rings > 0) {
    cv::Mat x0 = (l - meanL).mul(m01), mm = m01.clone();
    double f = 1;  // original pixels per correlation pixel
    while (std::max(x0.cols, x0.rows) > options.maxCorrelationSize) {
      cv::resize(x0, x0, cv::Size((x0.cols + 1) / 2, (x0.rows + 1) / 2), 0, 0, cv::INTER_AREA);
      cv::resize(mm, mm, cv::Size((mm.cols + 1) / 2, (mm.rows + 1) / 2), 0, 0, cv::INTER_AREA);
      f *= 2;
    }
    const int maxLag = static_cast<int>(std::ceil(options.ringEdges.back() / f)) + 2;
    const int pr = cv::getOptimalDFTSize(x0.rows + maxLag),
              pc = cv::getOptimalDFTSize(x0.cols + maxLag);
    cv::Mat A = autocorrelation(x0, pr, pc), N = autocorrelation(mm, pr, pc);
    const float n0 = N.at<float>(0, 0), var = A.at<float>(0, 0) / std::max(n0, 1e-12f);
    // ratio map around the origin (lags -maxLag..maxLag), invalid where the overlap is small
    const int side = 2 * maxLag + 1;
    cv::Mat ratio(side, side, CV_32FC1), valid(side, side, CV_32FC1);
    for (int dy = -maxLag; dy <= maxLag; ++dy)
      for (int dx = -maxLag; dx <= maxLag; ++dx) {
        const int yy = (dy + pr) % pr, xx = (dx + pc) % pc;
        const float n = N.at<float>(yy, xx);
        const bool ok = n > 0.25f * n0 && var > 1e-12f;
        ratio.at<float>(dy + maxLag, dx + maxLag) = ok ? A.at<float>(yy, xx) / (n * var) : 0.f;
        valid.at<float>(dy + maxLag, dx + maxLag) = ok ? 1.f : 0.f;
      }
    constexpr int kAngles = 24;
    for (int r = 0; r < rings; ++r) {
      double sum = 0, n = 0;
      float best = -1e9f;
      for (int t = 1; t <= 2; ++t) {
        const double rad =
            (options.ringEdges[r] + t / 3.0 * (options.ringEdges[r + 1] - options.ringEdges[r])) /
            f;
        for (int k = 0; k < kAngles; ++k) {
          // half the circle suffices: the autocorrelation is point-symmetric
          const double ang = M_PI * k / kAngles;
          const double x = maxLag + rad * std::cos(ang), y = maxLag + rad * std::sin(ang);
          float v = 0, ok = 0;
          if (!sampleAt(valid, x, y, &ok) || ok < 0.999f || !sampleAt(ratio, x, y, &v)) continue;
          sum += v;
          n += 1;
          best = std::max(best, v);
        }
      }
      out.push_back(n > 0 ? static_cast<float>(sum / n) : 0.f);
      out.push_back(n > 0 ? best : 0.f);
    }
  }
}

/// 3. Colour against brightness: the opponent channels a, b against log L, and their spread.
void appendColourStatistics(const cv::Mat& l, const cv::Mat& a, const cv::Mat& b, const cv::Mat& msk,
                            const cv::Mat& m01, double count, double meanL, float floor,
                            std::vector<float>& out) {
  const double ma = cv::sum(a)[0] / count, mb = cv::sum(b)[0] / count;
  double val = 0, caa = 0, cbb = 0, cal = 0, cbl = 0;
  for (int y = 0; y < l.rows; ++y)
    for (int x = 0; x < l.cols; ++x) {
      if (!msk.at<uint8_t>(y, x)) continue;
      const double dl = l.at<float>(y, x) - meanL, da = a.at<float>(y, x) - ma,
                   db = b.at<float>(y, x) - mb;
      val += dl * dl;
      caa += da * da;
      cbb += db * db;
      cal += da * dl;
      cbl += db * dl;
    }
  out.push_back(static_cast<float>(cal / (val + 1e-6 * count)));
  out.push_back(static_cast<float>(cbl / (val + 1e-6 * count)));
  out.push_back(std::log(static_cast<float>(std::sqrt(caa / count)) + floor));
  out.push_back(std::log(static_cast<float>(std::sqrt(cbb / count)) + floor));
  // blurred by 3 pixels: 1.5 on the half-size field (masked area averages)
  const cv::Size half((l.cols + 1) / 2, (l.rows + 1) / 2);
  cv::Mat ah, bh, mh;
  cv::resize(a, ah, half, 0, 0, cv::INTER_AREA);
  cv::resize(b, bh, half, 0, 0, cv::INTER_AREA);
  cv::resize(m01, mh, half, 0, 0, cv::INTER_AREA);
  ah /= cv::max(mh, 1e-6);
  bh /= cv::max(mh, 1e-6);
  const cv::Mat ab = maskedBlur(ah, mh, 1.5, nullptr), bb = maskedBlur(bh, mh, 1.5, nullptr);
  double s2a = 0, s2b = 0, sm = 0;
  for (int y = 0; y < half.height; ++y)
    for (int x = 0; x < half.width; ++x) {
      const double wt = mh.at<float>(y, x);
      if (wt <= 0) continue;
      s2a += wt * std::pow(ab.at<float>(y, x) - ma, 2);
      s2b += wt * std::pow(bb.at<float>(y, x) - mb, 2);
      sm += wt;
    }
  out.push_back(std::log(static_cast<float>(std::sqrt(s2a / std::max(sm, 1e-9))) + floor));
  out.push_back(std::log(static_cast<float>(std::sqrt(s2b / std::max(sm, 1e-9))) + floor));
}

}  // namespace

std::vector<float> computeStructureKey(const cv::Mat& image, const cv::Mat& mask,
                                       const TextureStructureOptions& options) {
  std::string why;
  PS_Check(options.IsValid(&why), "invalid TextureStructureOptions: " << why);
  PS_Check(image.type() == CV_32FC3 && mask.type() == CV_8UC1 && image.size() == mask.size(),
           "computeStructureKey: CV_32FC3 image and CV_8UC1 mask of one size expected");
  const cv::Rect box = cv::boundingRect(mask != 0);
  PS_Check(box.area() > 0, "computeStructureKey: empty mask");
  const cv::Mat img = image(box), msk = mask(box) != 0;

  // per-channel normalization by the masked mean: invariant to any per-channel light scale
  const cv::Scalar channelMean = cv::mean(img, msk);
  double norm[3];
  const double maxMean = std::max({channelMean[0], channelMean[1], channelMean[2]});
  for (int c = 0; c < 3; ++c) norm[c] = 1.0 / (channelMean[c] + 1e-6 * maxMean + 1e-12);
  cv::Mat m01;
  msk.convertTo(m01, CV_32F, 1.0 / 255.0);
  const float floor = options.logFloor;
  std::vector<cv::Mat> ch(3);
  cv::split(img, ch);
  for (int c = 0; c < 3; ++c) ch[c].convertTo(ch[c], CV_32F, norm[c], floor);  // x / mean + floor
  cv::Mat l = kLuminanceWeightsF[0] * ch[0] + kLuminanceWeightsF[1] * ch[1] +
              kLuminanceWeightsF[2] * ch[2],
          a, b;  // luminance + floor
  cv::log(l, l);
  for (int c = 0; c < 3; ++c) cv::log(ch[c], ch[c]);
  a = ch[0] - ch[1];
  b = ch[2] - ch[1];
  l.setTo(0, ~msk);
  a.setTo(0, ~msk);
  b.setTo(0, ~msk);
  const double count = std::max(1, cv::countNonZero(msk));
  const double meanL = cv::sum(l)[0] / count;
  std::vector<float> out;
  out.reserve(structureKeyLength(options));

  appendGradientStatistics(l, m01, options, out);
  appendAutocorrelationRings(l, m01, meanL, options, out);
  appendColourStatistics(l, a, b, msk, m01, count, meanL, floor, out);
  PS_CheckEQ(static_cast<int>(out.size()), structureKeyLength(options), "structure key length");
  return out;
}

}  // namespace ps
