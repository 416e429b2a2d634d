#include "photoscene/features/texture_loss.hpp"

#include "gabor_pyramid.hpp"
#include "gradient_check.hpp"
#include "ps_statistics.hpp"
#include "sliced_colour.hpp"
#include "photoscene/core/error.hpp"
#include "photoscene/core/image.hpp"
#include "photoscene/core/color.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace ps {

using namespace features_detail;

bool TextureLossOptions::IsValid(std::string* error) const {
  if (!descriptor.IsValid(error)) return false;
  std::string msg;
  const TextureLossWeights& w = weights;
  if (!ps.IsValid(error)) return false;
  if (!(w.colorMean >= 0 && w.colorStd >= 0 && w.bandMeanRe >= 0 && w.bandStdRe >= 0 &&
        w.bandMeanMag >= 0 && w.bandStdMag >= 0 && w.psAutoLowpass >= 0 && w.psAutoMagnitude >= 0 &&
        w.psCrossOrientation >= 0 && w.psCrossScale >= 0 && w.psColor >= 0 &&
        w.colorSliced >= 0 && w.bandShape >= 0))
    msg = "loss weights must be >= 0";
  else if (!w.scale.empty() && static_cast<int>(w.scale.size()) != descriptor.numScales)
    msg = "weights.scale must be empty or have numScales entries";
  else if (std::any_of(w.scale.begin(), w.scale.end(), [](float v) { return !(v >= 0); }))
    msg = "weights.scale entries must be >= 0";
  if (error) *error = msg;
  return msg.empty();
}

struct TextureLossTarget::Impl {
  TextureLossOptions options;
  GaborBank bank;
  MaskPyramid pyramid;
  TextureDescriptor descriptor;
  std::vector<double> targetValues;
  std::vector<double> entryWeight;  // weight_g / n_g / nu^2 per descriptor entry
  std::vector<int> entryGroup;
  cv::Size size;
  double nu = 1.0;
  // joint statistics (active when a ps weight is > 0)
  bool psActive = false;
  PsMask psMask;
  std::vector<double> psTarget, psEntryWeight;
  std::vector<int> psEntryGroup;
  std::vector<float> psValues;
  cv::Vec3d noise{0, 0, 0};  // the photo's pixel noise taken off targetValues
  // colour distribution (active when weights.colorSliced > 0)
  SlicedTarget sliced;
  // spectral shape (active when weights.bandShape > 0): the photo's band energy shares, its
  // pixel noise's energy taken off
  std::vector<double> shapeTarget;
};

namespace {

/// Each band's energy meanMag^2 + stdMag^2, in band order (s * numOrientations + k).
std::vector<double> bandEnergies(const std::vector<double>& values, const TextureDescriptorOptions& o) {
  const int K = o.numOrientations;
  std::vector<double> e(size_t(o.numScales * K));
  for (int s = 0; s < o.numScales; ++s)
    for (int k = 0; k < K; ++k) {
      const int i = bandIndex(o, s, k);
      e[size_t(s * K + k)] = values[i + kBandMeanMag] * values[i + kBandMeanMag] +
                             values[i + kBandStdMag] * values[i + kBandStdMag];
    }
  return e;
}

/// The energies over their sum (texture_loss.hpp's bandShape); all 0 when there is no energy.
std::vector<double> shares(std::vector<double> e, double* total = nullptr) {
  double sum = 0;
  for (double v : e) sum += v;
  if (total) *total = sum;
  for (double& v : e) v = sum > 1e-30 ? v / sum : 0.0;
  return e;
}

/// sqrt(max(0, v^2 - e2 - n2) + e2): a statistic v = sqrt(var + e2) with the variance n2 taken off.
double withoutVariance(double v, double n2, double e2) {
  return std::sqrt(std::max(0.0, v * v - e2 - n2) + e2);
}

/// The descriptor of white noise at the photo's estimated pixel noise (`noise`, per channel)
/// through the target's mask and filters (a fixed seed: the same target every time); empty when
/// the photo shows no noise.
std::vector<double> photoNoiseStatistics(const cv::Mat& photo, const cv::Mat& mask,
                                         const TextureLossTarget::Impl& m, cv::Vec3d* noise) {
  *noise = estimatePixelNoise(photo, mask);
  if (*noise == cv::Vec3d(0, 0, 0)) return {};
  cv::Mat image(photo.size(), CV_32FC3);
  cv::RNG rng(0x9e3779b97f4a7c15ULL);
  rng.fill(image, cv::RNG::NORMAL, cv::Scalar::all(0), cv::Scalar::all(1));
  image = image.mul(cv::Scalar((*noise)[0], (*noise)[1], (*noise)[2]));
  ForwardState ns;
  forwardDescriptor(image, m.pyramid, m.bank, m.options.descriptor, ns, false);
  return ns.values;
}

/// The spectral shape's target: the photo's band energy shares with the noise's band energy
/// (`noiseValues`, photoNoiseStatistics; empty: none) taken off each band first.
std::vector<double> shapeTargetOf(const std::vector<double>& values,
                                  const std::vector<double>& noiseValues,
                                  const TextureDescriptorOptions& o) {
  std::vector<double> e = bandEnergies(values, o);
  if (!noiseValues.empty()) {
    const std::vector<double> n = bandEnergies(noiseValues, o);
    for (size_t b = 0; b < e.size(); ++b) e[b] = std::max(0.0, e[b] - n[b]);
  }
  return shares(std::move(e));
}

/// Takes the photo's pixel noise off the target statistics (TextureLossOptions::photoNoiseFloor).
void subtractPhotoNoise(const cv::Mat& photo, const cv::Mat& mask, TextureLossTarget::Impl& m) {
  const TextureDescriptorOptions& o = m.options.descriptor;
  ForwardState ns;
  ns.values = photoNoiseStatistics(photo, mask, m, &m.noise);
  if (ns.values.empty()) return;
  const double e2 = static_cast<double>(o.epsilon) * o.epsilon;
  std::vector<double>& t = m.targetValues;
  for (int ch = 0; ch < 3; ++ch) t[3 + ch] = withoutVariance(t[3 + ch], m.noise[ch] * m.noise[ch], e2);
  for (int s = 0; s < o.numScales; ++s)
    for (int k = 0; k < o.numOrientations; ++k) {
      const int i = bandIndex(o, s, k);
      const auto var = [&](const std::vector<double>& v, int j) { return v[i + j] * v[i + j] - e2; };
      t[i + kBandStdRe] = withoutVariance(t[i + kBandStdRe], var(ns.values, kBandStdRe), e2);
      // the magnitudes' second moment, mean^2 + var
      const double photo2 = t[i + kBandMeanMag] * t[i + kBandMeanMag] + var(t, kBandStdMag);
      const double noise2 = ns.values[i + kBandMeanMag] * ns.values[i + kBandMeanMag] +
                            var(ns.values, kBandStdMag);
      const double f = photo2 > 0 ? std::sqrt(std::max(0.0, photo2 - noise2) / photo2) : 1.0;
      t[i + kBandMeanMag] *= f;
      t[i + kBandStdMag] = std::sqrt(std::max(0.0, var(t, kBandStdMag)) * f * f + e2);
    }
}

}  // namespace

cv::Vec3d estimatePixelNoise(const cv::Mat& photo, const cv::Mat& mask, int minPixels) {
  checkImage(photo, CV_32FC3, photo.size(), "estimatePixelNoise photo");
  checkImage(mask, CV_8UC1, photo.size(), "estimatePixelNoise mask");
  // the operator's response everywhere, read where the whole 3 x 3 window lies in the mask (the
  // mask eroded, the image's border counted as outside)
  static const cv::Matx33f kImmerkaer(1, -2, 1, -2, 4, -2, 1, -2, 1);
  cv::Mat response, interior;
  cv::filter2D(photo, response, CV_32F, kImmerkaer);
  cv::erode(mask, interior, cv::Mat(), cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  std::vector<float> r[3];
  for (int y = 0; y < photo.rows; ++y) {
    const uint8_t* in = interior.ptr<uint8_t>(y);
    const cv::Vec3f* v = response.ptr<cv::Vec3f>(y);
    for (int x = 0; x < photo.cols; ++x)
      if (in[x])
        for (int c = 0; c < 3; ++c) r[c].push_back(std::abs(v[x][c]));
  }
  if (static_cast<int>(r[0].size()) < std::max(1, minPixels)) return {0, 0, 0};
  cv::Vec3d sigma;
  for (int c = 0; c < 3; ++c) {
    std::vector<float>& v = r[c];
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    sigma[c] = v[v.size() / 2] / (0.6745 * 6.0);
  }
  return sigma;
}

struct TextureLossWorkspace {
  ForwardState state;
  PsState ps;
  SlicedState sliced;
};

TextureLossTarget::TextureLossTarget(const cv::Mat& photo, const cv::Mat& mask,
                                     const TextureLossOptions& options)
    : impl_(std::make_unique<Impl>()) {
  std::string err;
  PS_Check(options.IsValid(&err), "invalid TextureLossOptions: " << err);
  checkDescriptorInputs(photo, mask);
  Impl& m = *impl_;
  m.options = options;
  m.size = photo.size();
  const TextureDescriptorOptions& o = options.descriptor;
  m.bank = makeGaborBank(o);
  m.pyramid = makeMaskPyramid(mask, o, m.bank);
  m.psActive = options.weights.anyPs();
  ForwardState st;
  forwardDescriptor(photo, m.pyramid, m.bank, o, st, m.psActive);
  m.targetValues = st.values;
  m.descriptor = toDescriptor(st, m.pyramid, o);
  if (options.photoNoiseFloor) subtractPhotoNoise(photo, mask, m);
  if (options.weights.bandShape > 0) {
    // the render carries no pixel noise: its energy in the photo's bands would read as fine
    // structure the render must make up (photoNoiseFloor: already off targetValues)
    cv::Vec3d noise;
    m.shapeTarget = shapeTargetOf(
        m.targetValues,
        options.photoNoiseFloor ? std::vector<double>{} : photoNoiseStatistics(photo, mask, m, &noise), o);
  }
  if (options.normalizeByTarget) {
    const double lum = luminance(st.values[0], st.values[1], st.values[2]);
    m.nu = std::max(lum, 1e-3);
  }
  const int S = o.numScales, K = o.numOrientations, SK = S * K;
  const TextureLossWeights& w = options.weights;
  if (w.colorSliced > 0) m.sliced = makeSlicedTarget(st.rgb, m.pyramid.mask0, m.nu, m.noise);
  m.entryWeight.assign(descriptorLength(o), 0.0);
  m.entryGroup.assign(descriptorLength(o), 0);
  const double inv = 1.0 / (m.nu * m.nu);
  for (int ch = 0; ch < 3; ++ch) {
    m.entryWeight[ch] = w.colorMean / 3.0 * inv;
    m.entryGroup[ch] = 0;
    m.entryWeight[3 + ch] = w.colorStd / 3.0 * inv;
    m.entryGroup[3 + ch] = 1;
  }
  const float gw[4] = {w.bandMeanRe, w.bandStdRe, w.bandMeanMag, w.bandStdMag};
  for (int s = 0; s < S; ++s) {
    const double sw = w.scale.empty() ? 1.0 : w.scale[s];
    for (int k = 0; k < K; ++k) {
      for (int j = 0; j < 4; ++j) {
        const int i = bandIndex(o, s, k) + j;
        m.entryWeight[i] = gw[j] * sw / SK * inv;
        m.entryGroup[i] = 2 + j;
      }
    }
  }
  if (m.psActive) {
    m.psMask = makePsMask(m.pyramid, o, options.ps);
    PsState ps;
    forwardPs(st, m.pyramid, m.psMask, m.bank, o, options.ps, ps);
    m.psTarget = ps.values;
    m.psValues.assign(ps.values.begin(), ps.values.end());
    const TexturePsLayout L = texturePsLayout(o, options.ps);
    m.psEntryWeight.assign(L.length, 0.0);
    m.psEntryGroup.assign(L.length, 0);
    const int bounds[6] = {L.autoLowpass, L.autoMagnitude, L.crossOrientation,
                           L.crossScale,  L.color,         L.length};
    const float gw[5] = {w.psAutoLowpass, w.psAutoMagnitude, w.psCrossOrientation, w.psCrossScale,
                         w.psColor};
    for (int grp = 0; grp < 5; ++grp) {
      const int n = bounds[grp + 1] - bounds[grp];
      for (int i = bounds[grp]; i < bounds[grp + 1]; ++i) {
        // colour means and standard deviations are in linear units: divided by nu like the
        // descriptor's; the correlations are unitless
        const bool linear = grp == 4 && i < L.color + 6;
        m.psEntryWeight[i] = n > 0 ? gw[grp] / n * (linear ? inv : 1.0) : 0.0;
        m.psEntryGroup[i] = grp;
      }
    }
  }
}

TextureLossTarget::~TextureLossTarget() = default;
TextureLossTarget::TextureLossTarget(TextureLossTarget&&) noexcept = default;
TextureLossTarget& TextureLossTarget::operator=(TextureLossTarget&&) noexcept = default;

const TextureLossOptions& TextureLossTarget::options() const {
  return impl_->options;
}
const TextureDescriptor& TextureLossTarget::descriptor() const {
  return impl_->descriptor;
}
cv::Size TextureLossTarget::imageSize() const {
  return impl_->size;
}
cv::Rect TextureLossTarget::crop() const {
  return impl_->pyramid.crop;
}
double TextureLossTarget::normalizer() const {
  return impl_->nu;
}
const std::vector<float>& TextureLossTarget::psStatistics() const {
  return impl_->psValues;
}
cv::Vec3d TextureLossTarget::photoNoise() const {
  return impl_->noise;
}

double textureLossForward(TextureLossParams& params) {
  PS_Check(params.target != nullptr, "TextureLossParams.target is null");
  const TextureLossTarget::Impl& t = params.target->impl();
  checkImage(params.render, CV_32FC3, t.size, "texture loss render");
  PS_Check(allFinite(params.render(t.pyramid.crop)), "texture loss render has NaN or Inf values");
  if (!params.workspace) params.workspace = std::make_shared<TextureLossWorkspace>();
  ForwardState& st = params.workspace->state;
  forwardDescriptor(params.render, t.pyramid, t.bank, t.options.descriptor, st, true);
  double loss = 0.0;
  std::fill(std::begin(params.groupLoss), std::end(params.groupLoss), 0.0);
  std::fill(std::begin(params.psGroupLoss), std::end(params.psGroupLoss), 0.0);
  for (size_t i = 0; i < st.values.size(); ++i) {
    const double d = st.values[i] - t.targetValues[i];
    const double c = t.entryWeight[i] * d * d;
    params.groupLoss[t.entryGroup[i]] += c;
    loss += c;
  }
  params.renderPs.clear();
  if (t.psActive) {
    PsState& ps = params.workspace->ps;
    forwardPs(st, t.pyramid, t.psMask, t.bank, t.options.descriptor, t.options.ps, ps);
    for (size_t i = 0; i < ps.values.size(); ++i) {
      const double d = ps.values[i] - t.psTarget[i];
      const double c = t.psEntryWeight[i] * d * d;
      params.psGroupLoss[t.psEntryGroup[i]] += c;
      loss += c;
    }
    params.renderPs.assign(ps.values.begin(), ps.values.end());
  }
  params.shapeLoss = 0.0;
  if (t.options.weights.bandShape > 0) {
    const std::vector<double> r = shares(bandEnergies(st.values, t.options.descriptor));
    const std::vector<double>& p = t.shapeTarget;
    for (size_t b = 0; b < r.size(); ++b) params.shapeLoss += (r[b] - p[b]) * (r[b] - p[b]);
    params.shapeLoss *= t.options.weights.bandShape;
    loss += params.shapeLoss;
  }
  params.slicedLoss = 0.0;
  if (t.options.weights.colorSliced > 0) {
    params.slicedLoss = t.options.weights.colorSliced *
                        slicedForward(st.rgb, t.sliced, params.workspace->sliced);
    loss += params.slicedLoss;
  }
  params.loss = loss;
  params.renderDescriptor = toDescriptor(st, t.pyramid, t.options.descriptor);
  return loss;
}

void textureLossBackward(const TextureLossParams& params, float gradLoss, cv::Mat& gradRender,
                         bool accumulate) {
  PS_Check(params.target != nullptr, "TextureLossParams.target is null");
  PS_Check(params.workspace != nullptr, "textureLossBackward needs textureLossForward first");
  const TextureLossTarget::Impl& t = params.target->impl();
  const ForwardState& st = params.workspace->state;
  std::vector<double> g(st.values.size());
  for (size_t i = 0; i < g.size(); ++i)
    g[i] = gradLoss * 2.0 * t.entryWeight[i] * (st.values[i] - t.targetValues[i]);
  if (t.options.weights.bandShape > 0) {
    // d/d E_a of w sum_b (f_b - p_b)^2 with f_b = E_b / sum E: (1 / sum E) (d_a - sum_b d_b f_b),
    // d_b = 2 w (f_b - p_b); E_a = meanMag_a^2 + stdMag_a^2
    const TextureDescriptorOptions& o = t.options.descriptor;
    double sum = 0;
    const std::vector<double> r = shares(bandEnergies(st.values, o), &sum);
    const std::vector<double>& p = t.shapeTarget;
    if (sum > 1e-30) {
      double dotF = 0;
      std::vector<double> d(r.size());
      for (size_t b = 0; b < r.size(); ++b) {
        d[b] = 2.0 * t.options.weights.bandShape * (r[b] - p[b]);
        dotF += d[b] * r[b];
      }
      const int K = o.numOrientations;
      for (int sc = 0; sc < o.numScales; ++sc)
        for (int k = 0; k < K; ++k) {
          const size_t b = size_t(sc * K + k);
          const double dE = gradLoss * (d[b] - dotF) / sum;
          const int i = bandIndex(o, sc, k);
          for (const int j : {i + kBandMeanMag, i + kBandStdMag})
            g[size_t(j)] += dE * 2.0 * st.values[size_t(j)];
        }
    }
  }
  cv::Mat gradCrop;
  if (t.psActive) {
    const PsState& ps = params.workspace->ps;
    std::vector<double> gp(ps.values.size());
    for (size_t i = 0; i < gp.size(); ++i)
      gp[i] = gradLoss * 2.0 * t.psEntryWeight[i] * (ps.values[i] - t.psTarget[i]);
    ExtraGradients extra;
    backwardPs(st, t.pyramid, t.psMask, t.bank, t.options.descriptor, t.options.ps, ps, gp, extra);
    backwardDescriptor(t.pyramid, t.bank, t.options.descriptor, st, g, gradCrop, &extra);
  } else {
    backwardDescriptor(t.pyramid, t.bank, t.options.descriptor, st, g, gradCrop);
  }
  if (t.options.weights.colorSliced > 0)
    slicedBackward(t.sliced, params.workspace->sliced,
                   double(gradLoss) * t.options.weights.colorSliced, gradCrop);
  const bool reuse = accumulate && gradRender.type() == CV_32FC3 && gradRender.size() == t.size;
  if (!reuse) {
    gradRender.create(t.size, CV_32FC3);
    gradRender.setTo(cv::Scalar::all(0));
  }
  if (reuse) {
    cv::Mat roi = gradRender(t.pyramid.crop);
    roi += gradCrop;
  } else {
    gradCrop.copyTo(gradRender(t.pyramid.crop));
  }
}

TextureLossGradientCheck checkTextureLossGradient(const TextureLossTarget& target,
                                                  const cv::Mat& render,
                                                  const std::vector<cv::Point>& pixels,
                                                  double step) {
  TextureLossParams p;
  p.target = &target;
  p.render = render.clone();
  textureLossForward(p);
  cv::Mat grad;
  textureLossBackward(p, 1.0f, grad);
  TextureLossParams q;
  q.target = &target;
  return checkImageGradient(render, grad, pixels, step, [&](const cv::Mat& image) {
    q.render = image;
    return textureLossForward(q);
  });
}

TextureLossGradientCheck checkImageGradient(const cv::Mat& image, const cv::Mat& grad,
                                            const std::vector<cv::Point>& pixels, double step,
                                            const std::function<double(const cv::Mat&)>& loss) {
  cv::Mat work = image.clone();
  // Central difference on one entry with step s (the step actually taken in float).
  auto central = [&](float& v, double s) {
    const float orig = v;
    v = static_cast<float>(orig + s);
    const double up = loss(work);
    v = static_cast<float>(orig - s);
    const double down = loss(work);
    const double h = static_cast<double>(static_cast<float>(orig + s)) -
                     static_cast<double>(static_cast<float>(orig - s));
    v = orig;
    return (up - down) / h;
  };
  std::vector<double> analytic, numeric, numeric2;
  for (const cv::Point& px : pixels) {
    PS_Check(px.inside(cv::Rect(0, 0, image.cols, image.rows)), "pixel outside the image");
    for (int ch = 0; ch < 3; ++ch) {
      float& v = work.at<cv::Vec3f>(px)[ch];
      numeric.push_back(central(v, step));
      numeric2.push_back(central(v, 2 * step));
      analytic.push_back(grad.at<cv::Vec3f>(px)[ch]);
    }
  }
  return summarizeGradientCheck(analytic, numeric, numeric2);
}

TextureLossGradientCheck summarizeGradientCheck(const std::vector<double>& analytic,
                                                const std::vector<double>& numeric,
                                                const std::vector<double>& numeric2) {
  TextureLossGradientCheck r;
  double maxNum = 0.0;
  for (size_t i = 0; i < numeric.size(); ++i) {
    maxNum = std::max(maxNum, std::abs(numeric[i]));
    // the loss is accumulated in float: the two steps disagree by its round-off (the O(h^2)
    // truncation term is far smaller at these steps), which bounds what the check can resolve
    r.noise = std::max(r.noise, std::abs(numeric[i] - numeric2[i]));
  }
  r.maxNumeric = maxNum;
  r.floor = std::max({1e-3 * maxNum, 2.0 * r.noise, 1e-12});
  for (size_t i = 0; i < numeric.size(); ++i) {
    const double e = std::abs(analytic[i] - numeric[i]);
    r.maxAbsError = std::max(r.maxAbsError, e);
    r.maxRelError = std::max(r.maxRelError,
                             e / std::max({std::abs(analytic[i]), std::abs(numeric[i]), r.floor}));
  }
  r.checked = static_cast<int>(numeric.size());
  return r;
}

}  // namespace ps
