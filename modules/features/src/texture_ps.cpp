#include "photoscene/features/texture_ps.hpp"

#include "photoscene/core/error.hpp"
#include "photoscene/core/parallel.hpp"
#include "ps_statistics.hpp"

#include <algorithm>
#include <cmath>

namespace ps {

using namespace features_detail;

bool TexturePsOptions::IsValid(std::string* error) const {
  std::string msg;
  if (lowpassRadius < 0 || lowpassRadius > 8)
    msg = "lowpassRadius must be in [0, 8], got " + std::to_string(lowpassRadius);
  else if (magnitudeRadius < 0 || magnitudeRadius > 8)
    msg = "magnitudeRadius must be in [0, 8], got " + std::to_string(magnitudeRadius);
  if (error) *error = msg;
  return msg.empty();
}

int texturePsLagCount(int radius) {
  return 2 * radius * (radius + 1);
}

TexturePsLayout texturePsLayout(const TextureDescriptorOptions& d, const TexturePsOptions& o) {
  const int S = d.numScales, K = d.numOrientations;
  TexturePsLayout l;
  l.autoLowpass = 0;
  l.autoMagnitude = S * texturePsLagCount(o.lowpassRadius);
  l.crossOrientation = l.autoMagnitude + S * K * texturePsLagCount(o.magnitudeRadius);
  l.crossScale = l.crossOrientation + S * (K * (K - 1) / 2);
  l.color = l.crossScale + (S - 1) * K * K;
  l.length = l.color + 9;
  return l;
}

std::vector<float> computeTexturePsStatistics(const cv::Mat& image, const cv::Mat& mask,
                                              const TextureDescriptorOptions& descriptor,
                                              const TexturePsOptions& options) {
  std::string err;
  PS_Check(descriptor.IsValid(&err), "invalid TextureDescriptorOptions: " << err);
  PS_Check(options.IsValid(&err), "invalid TexturePsOptions: " << err);
  checkDescriptorInputs(image, mask);
  const GaborBank bank = makeGaborBank(descriptor);
  const MaskPyramid pyramid = makeMaskPyramid(mask, descriptor, bank);
  const PsMask psMask = makePsMask(pyramid, descriptor, options);
  ForwardState st;
  forwardDescriptor(image, pyramid, bank, descriptor, st, true);
  PsState ps;
  forwardPs(st, pyramid, psMask, bank, descriptor, options, ps);
  return std::vector<float>(ps.values.begin(), ps.values.end());
}

namespace features_detail {
namespace {

// Pairs counted by a lag whose pair weight is below this share of lag 0's read 0.
constexpr double kMinPairShare = 0.05;

// sum_x a(x) b(x + d) over the overlap (CV_64F maps of one size).
double lagSum(const cv::Mat& a, const cv::Mat& b, int dx, int dy) {
  const int H = a.rows, W = a.cols;
  // four partial sums: the compiler may not reorder one floating-point sum into vector lanes
  double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
  const int x0 = std::max(0, -dx), x1 = std::min(W, W - dx);
  for (int y = std::max(0, -dy); y < std::min(H, H - dy); ++y) {
    const double* pa = a.ptr<double>(y);
    const double* pb = b.ptr<double>(y + dy) + dx;
    int x = x0;
    for (; x + 3 < x1; x += 4) {
      s0 += pa[x] * pb[x];
      s1 += pa[x + 1] * pb[x + 1];
      s2 += pa[x + 2] * pb[x + 2];
      s3 += pa[x + 3] * pb[x + 3];
    }
    for (; x < x1; ++x) s0 += pa[x] * pb[x];
  }
  return (s0 + s1) + (s2 + s3);
}

// Adjoint of q -> g * sum_x q(x) q(x + d): gq(x) += g q(x + d), gq(x + d) += g q(x).
void lagAdjoint(const cv::Mat& q, int dx, int dy, double g, cv::Mat& gq) {
  const int H = q.rows, W = q.cols;
  for (int y = std::max(0, -dy); y < std::min(H, H - dy); ++y) {
    const double* p0 = q.ptr<double>(y);
    const double* p1 = q.ptr<double>(y + dy);
    double* g0 = gq.ptr<double>(y);
    double* g1 = gq.ptr<double>(y + dy);
    for (int x = std::max(0, -dx); x < std::min(W, W - dx); ++x) {
      g0[x] += g * p1[x + dx];
      g1[x + dx] += g * p0[x];
    }
  }
}

cv::Mat toDouble(const cv::Mat& m) {
  cv::Mat out;
  m.convertTo(out, CV_64F);
  return out;
}

// c = f - sum w f (w sums to 1, or is all 0).
cv::Mat center(const cv::Mat& f, const cv::Mat& w) {
  cv::Mat c = toDouble(f);
  c -= cv::Scalar(w.dot(c));
  return c;
}

// Adjoint of center: g_f = g_c - w sum g_c.
cv::Mat uncenter(const cv::Mat& gc, const cv::Mat& w) {
  return gc - w * cv::sum(gc)[0];
}

double weightedSquare(const cv::Mat& c, const cv::Mat& w) {
  return w.dot(c.mul(c));
}

// Normalized masked autocorrelation of centered map c with pair weights u (texture_ps.hpp).
void autocorrelation(const cv::Mat& c, const cv::Mat& u, const PsMask& pm, int level,
                     const std::vector<cv::Point>& lags, double eps2, double* out) {
  const cv::Mat q = u.mul(c);
  const double d0 = pm.pairAt(level, {0, 0});
  if (!(d0 > 0)) {
    std::fill(out, out + lags.size(), 0.0);
    return;
  }
  const double den = lagSum(q, q, 0, 0) / d0 + eps2;
  for (size_t i = 0; i < lags.size(); ++i) {
    const double d = pm.pairAt(level, lags[i]);
    out[i] = d > kMinPairShare * d0 ? lagSum(q, q, lags[i].x, lags[i].y) / d / den : 0.0;
  }
}

// d out / d c of autocorrelation given d out / d entries g (returns an empty Mat if g is all 0).
cv::Mat autocorrelationBackward(const cv::Mat& c, const cv::Mat& u, const PsMask& pm, int level,
                                const std::vector<cv::Point>& lags, double eps2, const double* g) {
  if (std::all_of(g, g + lags.size(), [](double v) { return v == 0.0; })) return cv::Mat();
  const double d0 = pm.pairAt(level, {0, 0});
  if (!(d0 > 0)) return cv::Mat();
  const cv::Mat q = u.mul(c);
  const double den = lagSum(q, q, 0, 0) / d0 + eps2;
  cv::Mat gq = cv::Mat::zeros(q.size(), CV_64F);
  double gA0 = 0.0;
  for (size_t i = 0; i < lags.size(); ++i) {
    const double d = pm.pairAt(level, lags[i]);
    if (!(d > kMinPairShare * d0) || g[i] == 0.0) continue;
    const double ad = lagSum(q, q, lags[i].x, lags[i].y) / d;
    gA0 -= g[i] * ad / (den * den);
    lagAdjoint(q, lags[i].x, lags[i].y, g[i] / (den * d), gq);
  }
  gq += q * (2.0 * gA0 / d0);
  return u.mul(gq);
}

// The opponent transform's rows.
constexpr double kInvSqrt2 = 0.70710678118654752, kInvSqrt6 = 0.40824829046386302,
                 kInvSqrt3 = 0.57735026918962576;
const double kOpp[3][3] = {{kInvSqrt2, -kInvSqrt2, 0.0},
                           {kInvSqrt6, kInvSqrt6, -2.0 * kInvSqrt6},
                           {kInvSqrt3, kInvSqrt3, kInvSqrt3}};
const int kOppPairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};

}  // namespace

std::vector<cv::Point> psLags(int radius) {
  std::vector<cv::Point> out;
  for (int dy = 0; dy <= radius; ++dy)
    for (int dx = -radius; dx <= radius; ++dx)
      if (dy > 0 || dx > 0) out.emplace_back(dx, dy);
  return out;
}

PsMask makePsMask(const MaskPyramid& p, const TextureDescriptorOptions& o,
                  const TexturePsOptions& po) {
  PsMask m;
  m.radius = std::max(po.lowpassRadius, po.magnitudeRadius);
  const int R = m.radius;
  m.pair.resize(o.numScales);
  for (int s = 0; s < o.numScales; ++s) {
    const cv::Mat u = toDouble(p.weight[s]);
    m.pair[s].assign((2 * R + 1) * (R + 1), 0.0);
    for (int dy = 0; dy <= R; ++dy)
      for (int dx = -R; dx <= R; ++dx) m.pair[s][dy * (2 * R + 1) + dx + R] = lagSum(u, u, dx, dy);
  }
  return m;
}

void forwardPs(const ForwardState& st, const MaskPyramid& p, const PsMask& pm,
               const GaborBank& bank, const TextureDescriptorOptions& o, const TexturePsOptions& po,
               PsState& ps) {
  const int S = o.numScales, K = o.numOrientations;
  PS_Check(static_cast<int>(st.mag.size()) == S * K && !st.mag[0].empty(),
           "texture PS statistics need a forward pass that kept its intermediates");
  const TexturePsLayout L = texturePsLayout(o, po);
  const double eps2 = o.epsilon * o.epsilon;
  ps.values.assign(L.length, 0.0);
  std::vector<cv::Mat> w(S);
  for (int s = 0; s < S; ++s) w[s] = toDouble(p.weight[s]);
  const std::vector<cv::Point> lagsL = psLags(po.lowpassRadius), lagsM = psLags(po.magnitudeRadius);
  const int nL = static_cast<int>(lagsL.size()), nM = static_cast<int>(lagsM.size());

  ps.cz.assign(S, cv::Mat());
  for (int s = 0; s < S; ++s) {
    ps.cz[s] = center(st.z[s], w[s]);
    autocorrelation(ps.cz[s], w[s], pm, s, lagsL, eps2, &ps.values[L.autoLowpass + s * nL]);
  }
  ps.cm.assign(S * K, cv::Mat());
  std::vector<double> varM(S * K), varU(S * K, 0.0);
  parallelFor(0, S * K, [&](int64_t band) {
    const int s = static_cast<int>(band / K);
    ps.cm[band] = center(st.mag[band], w[s]);
    varM[band] = weightedSquare(ps.cm[band], w[s]) + eps2;
    autocorrelation(ps.cm[band], w[s], pm, s, lagsM, eps2, &ps.values[L.autoMagnitude + band * nM]);
  });
  int idx = L.crossOrientation;
  for (int s = 0; s < S; ++s)
    for (int k = 0; k < K; ++k)
      for (int l = k + 1; l < K; ++l) {
        const cv::Mat& a = ps.cm[s * K + k];
        const cv::Mat& b = ps.cm[s * K + l];
        ps.values[idx++] = w[s].dot(a.mul(b)) / std::sqrt(varM[s * K + k] * varM[s * K + l]);
      }
  ps.cu.assign(S * K, cv::Mat());
  for (int s = 0; s + 1 < S; ++s)
    for (int l = 0; l < K; ++l) {
      const int coarse = (s + 1) * K + l;
      const cv::Mat up = downsampleAdjoint(st.mag[coarse], st.z[s].size(), bank) * 4.0;
      ps.cu[coarse] = center(up, w[s]);
      varU[coarse] = weightedSquare(ps.cu[coarse], w[s]) + eps2;
      for (int k = 0; k < K; ++k)
        ps.values[L.crossScale + (s * K + k) * K + l] =
            w[s].dot(ps.cm[s * K + k].mul(ps.cu[coarse])) /
            std::sqrt(varM[s * K + k] * varU[coarse]);
    }

  // Opponent colours over the mask pixels.
  const int H = p.crop.height, W = p.crop.width;
  ps.opp = cv::Mat::zeros(H, W, CV_64FC3);
  double sum[3] = {0, 0, 0};
  for (int y = 0; y < H; ++y) {
    const cv::Vec3f* c = st.rgb.ptr<cv::Vec3f>(y);
    const float* m = p.mask0.ptr<float>(y);
    cv::Vec3d* q = ps.opp.ptr<cv::Vec3d>(y);
    for (int x = 0; x < W; ++x) {
      if (m[x] == 0.0f) continue;
      for (int i = 0; i < 3; ++i) {
        q[x][i] = kOpp[i][0] * c[x][0] + kOpp[i][1] * c[x][1] + kOpp[i][2] * c[x][2];
        sum[i] += q[x][i];
      }
    }
  }
  const double n = p.count;
  double mean[3], cov[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
  for (int i = 0; i < 3; ++i) mean[i] = sum[i] / n;
  for (int y = 0; y < H; ++y) {
    const cv::Vec3d* q = ps.opp.ptr<cv::Vec3d>(y);
    const float* m = p.mask0.ptr<float>(y);
    for (int x = 0; x < W; ++x) {
      if (m[x] == 0.0f) continue;
      const double d[3] = {q[x][0] - mean[0], q[x][1] - mean[1], q[x][2] - mean[2]};
      for (int i = 0; i < 3; ++i)
        for (int j = i; j < 3; ++j) cov[i][j] += d[i] * d[j];
    }
  }
  double sd[3];
  for (int i = 0; i < 3; ++i) {
    sd[i] = std::sqrt(std::max(0.0, cov[i][i] / n) + eps2);
    ps.values[L.color + i] = mean[i];
    ps.values[L.color + 3 + i] = sd[i];
  }
  for (int t = 0; t < 3; ++t) {
    const int i = kOppPairs[t][0], j = kOppPairs[t][1];
    ps.values[L.color + 6 + t] = cov[i][j] / n / (sd[i] * sd[j]);
  }
}

void backwardPs(const ForwardState& st, const MaskPyramid& p, const PsMask& pm,
                const GaborBank& bank, const TextureDescriptorOptions& o,
                const TexturePsOptions& po, const PsState& ps, const std::vector<double>& g,
                ExtraGradients& extra) {
  const int S = o.numScales, K = o.numOrientations;
  const TexturePsLayout L = texturePsLayout(o, po);
  PS_CheckEQ(static_cast<int>(g.size()), L.length, "PS gradient length");
  PS_Check(static_cast<int>(ps.cm.size()) == S * K, "backwardPs needs forwardPs first");
  const double eps2 = o.epsilon * o.epsilon;
  std::vector<cv::Mat> w(S);
  for (int s = 0; s < S; ++s) w[s] = toDouble(p.weight[s]);
  const std::vector<cv::Point> lagsL = psLags(po.lowpassRadius), lagsM = psLags(po.magnitudeRadius);
  const int nL = static_cast<int>(lagsL.size()), nM = static_cast<int>(lagsM.size());
  extra.mag.resize(S * K);
  extra.z.resize(S);
  auto addTo = [](cv::Mat& dst, const cv::Mat& src64) {
    cv::Mat f;
    src64.convertTo(f, CV_32F);
    if (dst.empty())
      dst = f;
    else
      dst += f;
  };

  // Low-pass autocorrelation -> z_s.
  for (int s = 0; s < S; ++s) {
    const cv::Mat gc =
        autocorrelationBackward(ps.cz[s], w[s], pm, s, lagsL, eps2, &g[L.autoLowpass + s * nL]);
    if (!gc.empty()) addTo(extra.z[s], uncenter(gc, w[s]));
  }

  // Everything on the centered magnitudes: d out / d cm per band (CV_64F, level size).
  std::vector<cv::Mat> gcm(S * K);
  std::vector<uint8_t> touched(S * K, 0);
  std::vector<double> varM(S * K), varU(S * K, 0.0);
  parallelFor(0, S * K, [&](int64_t band) {
    const int s = static_cast<int>(band / K);
    varM[band] = weightedSquare(ps.cm[band], w[s]) + eps2;
    gcm[band] = autocorrelationBackward(ps.cm[band], w[s], pm, s, lagsM, eps2,
                                        &g[L.autoMagnitude + band * nM]);
    touched[band] = !gcm[band].empty();
    if (gcm[band].empty()) gcm[band] = cv::Mat::zeros(ps.cm[band].size(), CV_64F);
  });
  // rho(a, b) = sum w a b / sqrt(Va Vb): d rho / d a = w (b / sqrt(Va Vb) - rho a / Va).
  auto corrBackward = [&](const cv::Mat& a, const cv::Mat& b, const cv::Mat& wl, double va,
                          double vb, double gr, cv::Mat& ga, cv::Mat& gb) {
    const double root = std::sqrt(va * vb);
    const double rho = wl.dot(a.mul(b)) / root;
    ga += wl.mul(b * (gr / root) - a * (gr * rho / va));
    gb += wl.mul(a * (gr / root) - b * (gr * rho / vb));
  };
  int idx = L.crossOrientation;
  for (int s = 0; s < S; ++s)
    for (int k = 0; k < K; ++k)
      for (int l = k + 1; l < K; ++l) {
        const double gr = g[idx++];
        if (gr == 0.0) continue;
        corrBackward(ps.cm[s * K + k], ps.cm[s * K + l], w[s], varM[s * K + k], varM[s * K + l], gr,
                     gcm[s * K + k], gcm[s * K + l]);
        touched[s * K + k] = touched[s * K + l] = 1;
      }
  for (int s = 0; s + 1 < S; ++s)
    for (int l = 0; l < K; ++l) {
      const int coarse = (s + 1) * K + l;
      bool any = false;
      for (int k = 0; k < K; ++k) any = any || g[L.crossScale + (s * K + k) * K + l] != 0.0;
      if (!any) continue;
      varU[coarse] = weightedSquare(ps.cu[coarse], w[s]) + eps2;
      cv::Mat gcu = cv::Mat::zeros(ps.cu[coarse].size(), CV_64F);
      for (int k = 0; k < K; ++k) {
        const double gr = g[L.crossScale + (s * K + k) * K + l];
        if (gr == 0.0) continue;
        corrBackward(ps.cm[s * K + k], ps.cu[coarse], w[s], varM[s * K + k], varU[coarse], gr,
                     gcm[s * K + k], gcu);
        touched[s * K + k] = 1;
      }
      // up = 4 * downsampleAdjoint(mag): its adjoint is 4 * downsample
      cv::Mat gup;
      uncenter(gcu, w[s]).convertTo(gup, CV_32F);
      cv::Mat gmag = downsample(gup, bank) * 4.0;
      cv::Mat gmag64;
      gmag.convertTo(gmag64, CV_64F);
      addTo(extra.mag[coarse], gmag64);
    }
  for (int band = 0; band < S * K; ++band) {
    if (!touched[band]) continue;
    addTo(extra.mag[band], uncenter(gcm[band], w[band / K]));
  }

  // Opponent colours -> crop pixels.
  const double* gc = &g[L.color];
  if (std::all_of(gc, gc + 9, [](double v) { return v == 0.0; })) return;
  const double n = p.count;
  double mean[3], sd[3], rho[3];
  for (int i = 0; i < 3; ++i) {
    mean[i] = ps.values[L.color + i];
    sd[i] = ps.values[L.color + 3 + i];
    rho[i] = ps.values[L.color + 6 + i];
  }
  const int H = p.crop.height, W = p.crop.width;
  if (extra.rgb.empty()) extra.rgb = cv::Mat::zeros(H, W, CV_32FC3);
  for (int y = 0; y < H; ++y) {
    const cv::Vec3d* q = ps.opp.ptr<cv::Vec3d>(y);
    const float* m = p.mask0.ptr<float>(y);
    cv::Vec3f* out = extra.rgb.ptr<cv::Vec3f>(y);
    for (int x = 0; x < W; ++x) {
      if (m[x] == 0.0f) continue;
      double d[3], go[3];
      for (int i = 0; i < 3; ++i) {
        d[i] = q[x][i] - mean[i];
        go[i] = gc[i] / n + gc[3 + i] * d[i] / (n * sd[i]);
      }
      for (int t = 0; t < 3; ++t) {
        const int i = kOppPairs[t][0], j = kOppPairs[t][1];
        const double gr = gc[6 + t];
        if (gr == 0.0) continue;
        go[i] += gr * (d[j] / (n * sd[i] * sd[j]) - rho[t] * d[i] / (n * sd[i] * sd[i]));
        go[j] += gr * (d[i] / (n * sd[i] * sd[j]) - rho[t] * d[j] / (n * sd[j] * sd[j]));
      }
      for (int c = 0; c < 3; ++c)
        out[x][c] +=
            static_cast<float>(kOpp[0][c] * go[0] + kOpp[1][c] * go[1] + kOpp[2][c] * go[2]);
    }
  }
}

}  // namespace features_detail
}  // namespace ps
