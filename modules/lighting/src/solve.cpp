#include "photoscene/lighting/solve.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "photoscene/core/error.hpp"
#include "photoscene/core/image.hpp"

namespace ps::lighting {

bool SolveOptions::IsValid(std::string* error) const {
  if (maxAlternations < 1 || !(tolerance > 0) || !(saturation > 0) || maxSamplesPerView < 1 ||
      !(dropShare >= 0 && dropShare < 1)) {
    if (error) *error = "maxAlternations >= 1, tolerance > 0, saturation > 0, maxSamplesPerView >= 1, dropShare in [0, 1)";
    return false;
  }
  return true;
}

Eigen::VectorXd nnls(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, int maxIterations) {
  const int n = static_cast<int>(A.cols());
  PS_CheckEQ(A.rows(), b.rows(), "nnls: A and b rows");
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
  if (n == 0) return x;
  // Work on the normal equations: n is small (lights), rows are many (pixels).
  const Eigen::MatrixXd AtA = A.transpose() * A;
  const Eigen::VectorXd Atb = A.transpose() * b;
  const double tol = 10 * std::numeric_limits<double>::epsilon() * std::max(1.0, AtA.cwiseAbs().maxCoeff()) * n;
  std::vector<bool> passive(n, false);
  if (maxIterations <= 0) maxIterations = 3 * n + 10;
  auto solvePassive = [&](Eigen::VectorXd& s) {
    std::vector<int> idx;
    for (int j = 0; j < n; ++j)
      if (passive[j]) idx.push_back(j);
    s.setZero(n);
    if (idx.empty()) return;
    const int k = static_cast<int>(idx.size());
    Eigen::MatrixXd M(k, k);
    Eigen::VectorXd r(k);
    for (int i = 0; i < k; ++i) {
      r[i] = Atb[idx[i]];
      for (int j = 0; j < k; ++j) M(i, j) = AtA(idx[i], idx[j]);
    }
    const Eigen::VectorXd sol = M.ldlt().solve(r);
    for (int i = 0; i < k; ++i) s[idx[i]] = std::isfinite(sol[i]) ? sol[i] : 0.0;
  };
  Eigen::VectorXd w = Atb - AtA * x;
  for (int outer = 0; outer < maxIterations; ++outer) {
    int best = -1;
    double wmax = tol;
    for (int j = 0; j < n; ++j)
      if (!passive[j] && w[j] > wmax) {
        wmax = w[j];
        best = j;
      }
    if (best < 0) break;
    passive[best] = true;
    Eigen::VectorXd s;
    for (int inner = 0; inner < 3 * n + 10; ++inner) {
      solvePassive(s);
      bool feasible = true;
      double alpha = 1.0;
      for (int j = 0; j < n; ++j) {
        if (passive[j] && s[j] <= 0) {
          feasible = false;
          const double denom = x[j] - s[j];
          if (denom > 0) alpha = std::min(alpha, x[j] / denom);
        }
      }
      if (feasible) {
        x = s;
        break;
      }
      x += alpha * (s - x);
      for (int j = 0; j < n; ++j)
        if (passive[j] && x[j] <= tol) {
          passive[j] = false;
          x[j] = 0;
        }
    }
    w = Atb - AtA * x;
  }
  for (int j = 0; j < n; ++j) x[j] = std::max(0.0, x[j]);
  return x;
}

namespace {

constexpr double kMinFactor = 1e-3, kMaxFactor = 1e3;  ///< a region's reflectance factor
/// the share of the photos' energy from which light of known radiance (given, or pinned to the
/// pixels that show it) sets the factors' scale
constexpr double kKnownLightShare = 0.05;

/// Usable samples of one view: photo values and per-light values, 3 channels each.
struct Samples {
  std::vector<float> photo;                 // 3 per sample
  std::vector<std::vector<float>> light;    // per light, 3 per sample
  std::vector<float> given;                 // 3 per sample: ViewLightData::given (0: none)
  std::vector<int> region;                  // per sample: ViewLightData::regions (-1: none)
  int count = 0;
};

/// Usable pixels of one view where one light is seen directly: photo and that light's values.
struct DirectSamples {
  std::vector<float> photo, light, given;  // 3 per sample
  int count = 0;
};

bool usablePhoto(const cv::Vec3f& p, double saturation) {
  bool ok = true;
  for (int c = 0; c < 3; ++c) ok &= std::isfinite(p[c]) && p[c] < saturation && p[c] >= 0;
  return ok;
}

bool usablePixel(const ViewLightData& v, int y, int x, double saturation) {
  bool ok = usablePhoto(v.photo.at<cv::Vec3f>(y, x), saturation);
  for (const cv::Mat& l : v.perLight) {
    const cv::Vec3f& q = l.at<cv::Vec3f>(y, x);
    for (int c = 0; c < 3; ++c) ok &= std::isfinite(q[c]);
  }
  if (!v.given.empty()) {
    const cv::Vec3f& g = v.given.at<cv::Vec3f>(y, x);
    for (int c = 0; c < 3; ++c) ok &= std::isfinite(g[c]);
  }
  return ok;
}

cv::Vec3f givenAt(const ViewLightData& v, cv::Point q) {
  return v.given.empty() ? cv::Vec3f(0, 0, 0) : v.given.at<cv::Vec3f>(q);
}

/// Per light, the usable pixels of ViewLightData::direct (every one: they are few).
std::vector<DirectSamples> gatherDirect(const ViewLightData& v, int lights, const SolveOptions& o) {
  std::vector<DirectSamples> out(lights);
  if (v.direct.empty()) return out;
  PS_CheckEQ(static_cast<int>(v.direct.size()), lights,
             "lighting: ViewLightData::direct needs one mask per light (or none)");
  for (int k = 0; k < lights; ++k) {
    const cv::Mat& m = v.direct[k];
    if (m.empty()) continue;
    checkImage(m, CV_8UC1, v.photo.size(), "lighting: direct mask");
    for (int y = 0; y < m.rows; ++y)
      for (int x = 0; x < m.cols; ++x) {
        if (!m.at<uint8_t>(y, x) || !usablePixel(v, y, x, o.saturation)) continue;
        const cv::Vec3f &p = v.photo.at<cv::Vec3f>(y, x), &l = v.perLight[k].at<cv::Vec3f>(y, x);
        const cv::Vec3f g = givenAt(v, {x, y});
        for (int c = 0; c < 3; ++c) {
          out[k].photo.push_back(p[c]);
          out[k].light.push_back(l[c]);
          out[k].given.push_back(g[c]);
        }
        ++out[k].count;
      }
  }
  return out;
}

/// Every how many usable pixels of a view one is a sample (the fixed grid above maxSamplesPerView).
size_t sampleStride(size_t usable, const SolveOptions& o) {
  const size_t most = static_cast<size_t>(o.maxSamplesPerView);
  return std::max<size_t>(1, (usable + most - 1) / most);
}

Samples gather(const ViewLightData& v, int lights, const SolveOptions& o) {
  checkImage(v.photo, CV_32FC3, "lighting: photo");
  checkImage(v.mask, CV_8UC1, v.photo.size(), "lighting: mask");
  PS_CheckEQ(static_cast<int>(v.perLight.size()), lights, "lighting: every view needs one image per light");
  for (const cv::Mat& l : v.perLight) checkImage(l, CV_32FC3, v.photo.size(), "lighting: per-light render");
  if (!v.regions.empty()) checkImage(v.regions, CV_32SC1, v.photo.size(), "lighting: regions");
  if (!v.given.empty()) checkImage(v.given, CV_32FC3, v.photo.size(), "lighting: given light");
  std::vector<cv::Point> usable;
  for (int y = 0; y < v.photo.rows; ++y) {
    const uint8_t* m = v.mask.ptr<uint8_t>(y);
    for (int x = 0; x < v.photo.cols; ++x) {
      if (m[x] && usablePixel(v, y, x, o.saturation)) usable.emplace_back(x, y);
    }
  }
  const size_t stride = sampleStride(usable.size(), o);
  Samples s;
  s.light.resize(lights);
  for (size_t i = 0; i < usable.size(); i += stride) {
    const cv::Point q = usable[i];
    const cv::Vec3f &p = v.photo.at<cv::Vec3f>(q), g = givenAt(v, q);
    for (int c = 0; c < 3; ++c) {
      s.photo.push_back(p[c]);
      s.given.push_back(g[c]);
    }
    s.region.push_back(v.regions.empty() ? -1 : std::max(-1, v.regions.at<int>(q)));
    for (int k = 0; k < lights; ++k) {
      const cv::Vec3f& l = v.perLight[k].at<cv::Vec3f>(q);
      for (int c = 0; c < 3; ++c) s.light[k].push_back(l[c]);
    }
    ++s.count;
  }
  return s;
}

}  // namespace

std::string LightSolution::summary() const {
  std::string s;
  char buf[200];
  for (size_t k = 0; k < intensity.size(); ++k) {
    std::snprintf(buf, sizeof buf, "light %zu: (%.4g, %.4g, %.4g)%s%s\n", k, intensity[k].x(), intensity[k].y(),
                  intensity[k].z(), dropped[k] ? " dropped" : "",
                  k < pinned.size() && pinned[k] ? " (from the pixels that show it)" : "");
    s += buf;
  }
  for (size_t v = 0; v < exposure.size(); ++v) {
    std::snprintf(buf, sizeof buf, "exposure %zu: %.4g\n", v, exposure[v]);
    s += buf;
  }
  std::snprintf(buf, sizeof buf, "residual rms %.4g of photo rms %.4g over %d samples, %d alternations", residualRms,
                photoRms, samples, alternations);
  return s + buf;
}

namespace {

/// solveLights on the gathered samples of every view (`total` of them in all): lights,
/// exposures and the regions' factors solved alternately, each step with the others fixed, in
/// rounds that drop the lights adding (almost) nothing.
class LightSolver {
 public:
  LightSolver(const std::vector<Samples>& data, const std::vector<std::vector<DirectSamples>>& direct,
              int lights, int total, const SolveOptions& options)
      : data_(data), direct_(direct), lights_(lights), total_(total), o_(options) {
    sol_.intensity.assign(lights, Vec3d::Zero());
    sol_.exposure.assign(data.size(), 1.0);
    sol_.dropped.assign(lights, false);
    sol_.samples = total;
    findPinned();
    for (int k = 0; k < lights; ++k) active_.push_back(k);
    prepareRegions();
  }

  LightSolution solve() {
    // With a pinned light and several views the exposures come from the solve without the pin,
    // then stay: a pinned light's intensity follows the exposures of the views that show it
    // (x = sum e_v L P / sum e_v^2 L^2) and those exposures follow the light, so where the window
    // is seen in one view only the two would trade along x e_v = const and drift (the
    // yardstick's window case ran to exposure 0 and an intensity of 1e153).
    solveExposures_ = o_.perViewExposure && data_.size() > 1;
    if (solveExposures_ &&
        std::find(sol_.pinned.begin(), sol_.pinned.end(), true) != sol_.pinned.end()) {
      SolveOptions unpinned = o_;
      unpinned.directMinPixels = 0;
      sol_.exposure = LightSolver(data_, direct_, lights_, total_, unpinned).solve().exposure;
      solveExposures_ = false;
    }
    for (int round = 0; round <= lights_; ++round) {
      alternate();
      if (!dropWeakLights() || active_.empty()) break;
    }
    sol_.residualRms = residual();
    return sol_;
  }

 private:
  // Which lights are pinned to the pixels that show them (SolveOptions::directMinPixels).
  void findPinned() {
    sol_.directPixels.assign(lights_, 0);
    sol_.pinned.assign(lights_, false);
    for (int k = 0; k < lights_; ++k) {
      double seen = 0;
      for (const auto& d : direct_) {
        sol_.directPixels[k] += d[k].count;
        for (float l : d[k].light) seen += double(l) * l;
      }
      sol_.pinned[k] = o_.directMinPixels > 0 && sol_.directPixels[k] >= o_.directMinPixels && seen > 0;
    }
  }

  // The regions' reflectance factors (1 where a sample has no region), their weights, and what
  // sets the common scale of light and reflectance (LightSolution::regionFactor).
  void prepareRegions() {
    for (const Samples& s : data_)
      for (int r : s.region) regions_ = std::max(regions_, r + 1);
    sol_.regionFactor.assign(regions_, Vec3d::Ones());
    regionWeight_.assign(regions_, 0.0);
    for (const Samples& s : data_)
      for (int r : s.region)
        if (r >= 0) regionWeight_[r] += 1;
    double givenSum = 0, photoSum = 0;
    for (const Samples& s : data_) {
      for (float g : s.given) givenSum += g;
      for (int i = 0; i < s.count; ++i)
        for (int c = 0; c < 3; ++c) {
          photoSum += s.photo[3 * i + c];
          if (s.region[i] >= 0) regionPhotoSum_ += s.photo[3 * i + c];
        }
    }
    givenScale_ = givenSum > 0 && givenSum >= kKnownLightShare * photoSum;
  }

  double factor(int r, int c) const { return r >= 0 ? sol_.regionFactor[r][c] : 1.0; }

  // the given light and the active lights' sum at sample i, channel c (before exposure and
  // factor)
  double lit(const Samples& s, int i, int c) const {
    double m = s.given[3 * i + c];
    for (int k : active_) m += sol_.intensity[k][c] * s.light[k][3 * i + c];
    return m;
  }

  // Whether the pinned lights send at least kKnownLightShare of the light on the regions (not
  // counting their own pixels).
  bool pinnedScale() const {
    double pinned = 0;
    for (const Samples& s : data_)
      for (int i = 0; i < s.count; ++i) {
        if (s.region[i] < 0) continue;
        for (int k : active_)
          if (sol_.pinned[k])
            for (int c = 0; c < 3; ++c) pinned += sol_.intensity[k][c] * s.light[k][3 * i + c];
      }
    return pinned > 0 && pinned >= kKnownLightShare * regionPhotoSum_;
  }

  double residual() {
    double err = 0, ref = 0;
    for (size_t v = 0; v < data_.size(); ++v) {
      const Samples& s = data_[v];
      for (int i = 0; i < s.count; ++i)
        for (int c = 0; c < 3; ++c) {
          const double d = sol_.exposure[v] * factor(s.region[i], c) * lit(s, i, c) - s.photo[3 * i + c];
          err += d * d;
          ref += double(s.photo[3 * i + c]) * s.photo[3 * i + c];
        }
    }
    sol_.photoRms = std::sqrt(ref / (3.0 * total_));
    return std::sqrt(err / (3.0 * total_));
  }

  // One round's alternation, until the residual stops changing.
  void alternate() {
    double previous = std::numeric_limits<double>::infinity();
    const int alternations = (solveExposures_ || regions_ > 0) ? o_.maxAlternations : 1;
    for (int it = 0; it < alternations; ++it) {
      for (int c = 0; c < 3; ++c) solveIntensities(c);
      if (solveExposures_) solveExposures();
      if (regions_ > 0) solveFactors();
      sol_.alternations = it + 1;
      const double r = residual();
      if (std::abs(previous - r) <= o_.tolerance * std::max(r, 1e-30)) break;
      previous = r;
    }
  }

  // Channel c's intensities for fixed exposures: the pinned lights from the pixels that show
  // them, then the others by NNLS over the rest of the photo.
  void solveIntensities(int c) {
    std::vector<int> free;
    for (int k : active_)
      if (!sol_.pinned[k]) free.push_back(k);
    for (int k : active_) {
      if (!sol_.pinned[k]) continue;
      double pl = 0, ll = 0;
      for (size_t v = 0; v < direct_.size(); ++v) {
        const DirectSamples& d = direct_[v][k];
        for (int i = 0; i < d.count; ++i) {
          const double l = sol_.exposure[v] * d.light[3 * i + c];
          pl += l * (d.photo[3 * i + c] - sol_.exposure[v] * d.given[3 * i + c]);
          ll += l * l;
        }
      }
      sol_.intensity[k][c] = ll > 0 ? std::max(0.0, pl / ll) : 0.0;
    }
    const int n = static_cast<int>(free.size());
    if (n == 0) return;
    Eigen::MatrixXd A(total_, n);
    Eigen::VectorXd b(total_);
    int row = 0;
    for (size_t v = 0; v < data_.size(); ++v) {
      const Samples& s = data_[v];
      for (int i = 0; i < s.count; ++i, ++row) {
        const double ef = sol_.exposure[v] * factor(s.region[i], c);
        for (int j = 0; j < n; ++j) A(row, j) = ef * s.light[free[j]][3 * i + c];
        double pinnedPart = s.given[3 * i + c];
        for (int k : active_)
          if (sol_.pinned[k]) pinnedPart += sol_.intensity[k][c] * s.light[k][3 * i + c];
        b[row] = s.photo[3 * i + c] - ef * pinnedPart;
      }
    }
    const Eigen::VectorXd x = nnls(A, b);
    for (int j = 0; j < n; ++j) sol_.intensity[free[j]][c] = x[j];
  }

  // Exposures for fixed intensities (view 0 is the reference).
  void solveExposures() {
    for (size_t v = 1; v < data_.size(); ++v) {
      const Samples& s = data_[v];
      double pm = 0, mm = 0;
      for (int i = 0; i < s.count; ++i)
        for (int c = 0; c < 3; ++c) {
          const double m = factor(s.region[i], c) * lit(s, i, c);
          pm += m * s.photo[3 * i + c];
          mm += m * m;
        }
      sol_.exposure[v] = mm > 0 ? pm / mm : 1.0;
    }
  }

  // The regions' factors for fixed lights and exposures, then the gauge: their pixel-weighted
  // log-mean is 0 (light and reflectance trade a scale per channel), unless light of known
  // radiance sets that scale.
  void solveFactors() {
    std::vector<Vec3d> pm(regions_, Vec3d::Zero()), mm(regions_, Vec3d::Zero());
    for (size_t v = 0; v < data_.size(); ++v) {
      const Samples& s = data_[v];
      for (int i = 0; i < s.count; ++i) {
        const int r = s.region[i];
        if (r < 0) continue;
        for (int c = 0; c < 3; ++c) {
          const double m = sol_.exposure[v] * lit(s, i, c);
          pm[r][c] += m * s.photo[3 * i + c];
          mm[r][c] += m * m;
        }
      }
    }
    Vec3d logMean = Vec3d::Zero();
    double weight = 0;
    for (int r = 0; r < regions_; ++r) {
      if (regionWeight_[r] <= 0) continue;
      for (int c = 0; c < 3; ++c)
        sol_.regionFactor[r][c] = mm[r][c] > 0 ? std::clamp(pm[r][c] / mm[r][c], kMinFactor, kMaxFactor) : 1.0;
      logMean += regionWeight_[r] * sol_.regionFactor[r].array().log().matrix();
      weight += regionWeight_[r];
    }
    // light of given radiance sets every channel's scale: no gauge; a pinned light sets the
    // colour, the guesses the level (one scale over the channels); else one scale per channel
    if (weight > 0 && !givenScale_) {
      Vec3d g = (logMean / weight).array().exp().matrix();
      if (o_.pinnedLightSetsColour && pinnedScale()) g.setConstant(std::cbrt(g.prod()));
      for (Vec3d& f : sol_.regionFactor) f = f.cwiseQuotient(g);
    }
  }

  // Drops the lights that add nothing (zero) or almost nothing to the model's energy; true when
  // any was dropped (the rest are solved again).
  bool dropWeakLights() {
    double energyAll = 0;
    std::vector<double> energy(lights_, 0.0);
    for (const Samples& s : data_)
      for (int k : active_)
        for (int i = 0; i < s.count; ++i)
          for (int c = 0; c < 3; ++c)
            energy[k] += factor(s.region[i], c) * sol_.intensity[k][c] * s.light[k][3 * i + c];
    for (int k : active_) energyAll += energy[k];
    for (const Samples& s : data_)  // the given light's share counts in the whole
      for (int i = 0; i < s.count; ++i)
        for (int c = 0; c < 3; ++c) energyAll += factor(s.region[i], c) * s.given[3 * i + c];
    std::vector<int> keep;
    for (int k : active_) {
      const bool zero = sol_.intensity[k].maxCoeff() <= 0;
      if (zero || (energyAll > 0 && energy[k] < o_.dropShare * energyAll)) {
        sol_.dropped[k] = true;
        sol_.intensity[k].setZero();
      } else {
        keep.push_back(k);
      }
    }
    if (keep.size() == active_.size()) return false;
    active_ = keep;
    return true;
  }

  const std::vector<Samples>& data_;
  const std::vector<std::vector<DirectSamples>>& direct_;
  const int lights_, total_;
  const SolveOptions& o_;
  LightSolution sol_;
  std::vector<int> active_;          // lights not dropped
  int regions_ = 0;
  std::vector<double> regionWeight_;  // samples per region
  double regionPhotoSum_ = 0;         // the photo over the regions' samples
  bool givenScale_ = false;           // light of given radiance sets the scale
  bool solveExposures_ = false;
};

}  // namespace

cv::Mat solvePixels(const cv::Mat& photo, const cv::Mat& mask, const SolveOptions& options) {
  checkImage(photo, CV_32FC3, "lighting: photo");
  checkImage(mask, CV_8UC1, photo.size(), "lighting: mask");
  std::vector<cv::Point> usable;
  for (int y = 0; y < photo.rows; ++y) {
    const uint8_t* m = mask.ptr<uint8_t>(y);
    const cv::Vec3f* p = photo.ptr<cv::Vec3f>(y);
    for (int x = 0; x < photo.cols; ++x)
      if (m[x] && usablePhoto(p[x], options.saturation)) usable.emplace_back(x, y);
  }
  cv::Mat out = cv::Mat::zeros(photo.size(), CV_8UC1);
  const size_t stride = sampleStride(usable.size(), options);
  for (size_t i = 0; i < usable.size(); i += stride) out.at<uint8_t>(usable[i]) = 255;
  return out;
}

LightSolution solveLights(const std::vector<ViewLightData>& views, const SolveOptions& options) {
  std::string why;
  PS_Check(options.IsValid(&why), why);
  PS_Check(!views.empty(), "solveLights: no views");
  const int lights = static_cast<int>(views[0].perLight.size());
  std::vector<Samples> data;
  std::vector<std::vector<DirectSamples>> direct;
  int total = 0;
  for (const auto& v : views) {
    data.push_back(gather(v, lights, options));
    direct.push_back(gatherDirect(v, lights, options));
    total += data.back().count;
  }
  PS_Check(total > 0, "solveLights: no usable pixel in any view (masks empty or photos saturated)");
  return LightSolver(data, direct, lights, total, options).solve();
}

}  // namespace ps::lighting
