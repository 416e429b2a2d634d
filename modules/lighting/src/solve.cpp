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

/// solveLights on the gathered samples of every view (`total` of them in all).
LightSolution solveSamples(const std::vector<Samples>& data,
                           const std::vector<std::vector<DirectSamples>>& direct, int lights,
                           int total, const SolveOptions& options) {
  LightSolution sol;
  sol.intensity.assign(lights, Vec3d::Zero());
  sol.exposure.assign(data.size(), 1.0);
  sol.dropped.assign(lights, false);
  sol.samples = total;
  sol.directPixels.assign(lights, 0);
  sol.pinned.assign(lights, false);
  for (int k = 0; k < lights; ++k) {
    double seen = 0;
    for (const auto& d : direct) {
      sol.directPixels[k] += d[k].count;
      for (float l : d[k].light) seen += double(l) * l;
    }
    sol.pinned[k] = options.directMinPixels > 0 && sol.directPixels[k] >= options.directMinPixels &&
                    seen > 0;
  }

  std::vector<int> active;
  for (int k = 0; k < lights; ++k) active.push_back(k);

  // the regions' reflectance factors (1 where a sample has no region)
  int regions = 0;
  for (const Samples& s : data)
    for (int r : s.region) regions = std::max(regions, r + 1);
  sol.regionFactor.assign(regions, Vec3d::Ones());
  std::vector<double> regionWeight(regions, 0.0);
  for (const Samples& s : data)
    for (int r : s.region)
      if (r >= 0) regionWeight[r] += 1;
  auto factor = [&](int r, int c) { return r >= 0 ? sol.regionFactor[r][c] : 1.0; };
  // what sets the common scale of light and reflectance (LightSolution::regionFactor)
  double givenSum = 0, photoSum = 0, regionPhotoSum = 0;
  for (const Samples& s : data) {
    for (float g : s.given) givenSum += g;
    for (int i = 0; i < s.count; ++i)
      for (int c = 0; c < 3; ++c) {
        photoSum += s.photo[3 * i + c];
        if (s.region[i] >= 0) regionPhotoSum += s.photo[3 * i + c];
      }
  }
  const bool givenScale = givenSum > 0 && givenSum >= kKnownLightShare * photoSum;
  // ... of the light on the regions (not counting the pinned light's own pixels)
  auto pinnedScale = [&] {
    double pinned = 0;
    for (const Samples& s : data)
      for (int i = 0; i < s.count; ++i) {
        if (s.region[i] < 0) continue;
        for (int k : active)
          if (sol.pinned[k])
            for (int c = 0; c < 3; ++c) pinned += sol.intensity[k][c] * s.light[k][3 * i + c];
      }
    return pinned > 0 && pinned >= kKnownLightShare * regionPhotoSum;
  };
  // the given light and the active lights' sum at sample i, channel c (before exposure and
  // factor)
  auto lit = [&](const Samples& s, int i, int c) {
    double m = s.given[3 * i + c];
    for (int k : active) m += sol.intensity[k][c] * s.light[k][3 * i + c];
    return m;
  };

  auto residual = [&]() {
    double err = 0, ref = 0;
    for (size_t v = 0; v < data.size(); ++v) {
      const Samples& s = data[v];
      for (int i = 0; i < s.count; ++i)
        for (int c = 0; c < 3; ++c) {
          const double d = sol.exposure[v] * factor(s.region[i], c) * lit(s, i, c) - s.photo[3 * i + c];
          err += d * d;
          ref += double(s.photo[3 * i + c]) * s.photo[3 * i + c];
        }
    }
    sol.photoRms = std::sqrt(ref / (3.0 * total));
    return std::sqrt(err / (3.0 * total));
  };

  // With a pinned light and several views the exposures come from the solve without the pin,
  // then stay: a pinned light's intensity follows the exposures of the views that show it
  // (x = sum e_v L P / sum e_v^2 L^2) and those exposures follow the light, so where the window
  // is seen in one view only the two would trade along x e_v = const and drift (the yardstick's
  // window case ran to exposure 0 and an intensity of 1e153).
  bool solveExposures = options.perViewExposure && data.size() > 1;
  if (solveExposures && std::find(sol.pinned.begin(), sol.pinned.end(), true) != sol.pinned.end()) {
    SolveOptions unpinned = options;
    unpinned.directMinPixels = 0;
    sol.exposure = solveSamples(data, direct, lights, total, unpinned).exposure;
    solveExposures = false;
  }
  for (int round = 0; round <= lights; ++round) {
    double previous = std::numeric_limits<double>::infinity();
    const int alternations = (solveExposures || regions > 0) ? options.maxAlternations : 1;
    for (int it = 0; it < alternations; ++it) {
      // intensities per channel for fixed exposures: the pinned lights from the pixels that
      // show them, then the others by NNLS over the rest of the photo
      std::vector<int> free;
      for (int k : active)
        if (!sol.pinned[k]) free.push_back(k);
      for (int c = 0; c < 3; ++c) {
        for (int k : active) {
          if (!sol.pinned[k]) continue;
          double pl = 0, ll = 0;
          for (size_t v = 0; v < direct.size(); ++v) {
            const DirectSamples& d = direct[v][k];
            for (int i = 0; i < d.count; ++i) {
              const double l = sol.exposure[v] * d.light[3 * i + c];
              pl += l * (d.photo[3 * i + c] - sol.exposure[v] * d.given[3 * i + c]);
              ll += l * l;
            }
          }
          sol.intensity[k][c] = ll > 0 ? std::max(0.0, pl / ll) : 0.0;
        }
        const int n = static_cast<int>(free.size());
        if (n == 0) continue;
        Eigen::MatrixXd A(total, n);
        Eigen::VectorXd b(total);
        int row = 0;
        for (size_t v = 0; v < data.size(); ++v) {
          const Samples& s = data[v];
          for (int i = 0; i < s.count; ++i, ++row) {
            const double ef = sol.exposure[v] * factor(s.region[i], c);
            for (int j = 0; j < n; ++j) A(row, j) = ef * s.light[free[j]][3 * i + c];
            double pinnedPart = s.given[3 * i + c];
            for (int k : active)
              if (sol.pinned[k]) pinnedPart += sol.intensity[k][c] * s.light[k][3 * i + c];
            b[row] = s.photo[3 * i + c] - ef * pinnedPart;
          }
        }
        const Eigen::VectorXd x = nnls(A, b);
        for (int j = 0; j < n; ++j) sol.intensity[free[j]][c] = x[j];
      }
      // exposures for fixed intensities (view 0 is the reference)
      if (solveExposures) {
        for (size_t v = 1; v < data.size(); ++v) {
          const Samples& s = data[v];
          double pm = 0, mm = 0;
          for (int i = 0; i < s.count; ++i)
            for (int c = 0; c < 3; ++c) {
              const double m = factor(s.region[i], c) * lit(s, i, c);
              pm += m * s.photo[3 * i + c];
              mm += m * m;
            }
          sol.exposure[v] = mm > 0 ? pm / mm : 1.0;
        }
      }
      // the regions' factors for fixed lights and exposures, then the gauge: their pixel-weighted
      // log-mean is 0 (light and reflectance trade a scale per channel), unless light of known
      // radiance sets that scale
      if (regions > 0) {
        std::vector<Vec3d> pm(regions, Vec3d::Zero()), mm(regions, Vec3d::Zero());
        for (size_t v = 0; v < data.size(); ++v) {
          const Samples& s = data[v];
          for (int i = 0; i < s.count; ++i) {
            const int r = s.region[i];
            if (r < 0) continue;
            for (int c = 0; c < 3; ++c) {
              const double m = sol.exposure[v] * lit(s, i, c);
              pm[r][c] += m * s.photo[3 * i + c];
              mm[r][c] += m * m;
            }
          }
        }
        Vec3d logMean = Vec3d::Zero();
        double weight = 0;
        for (int r = 0; r < regions; ++r) {
          if (regionWeight[r] <= 0) continue;
          for (int c = 0; c < 3; ++c)
            sol.regionFactor[r][c] = mm[r][c] > 0 ? std::clamp(pm[r][c] / mm[r][c], kMinFactor, kMaxFactor) : 1.0;
          logMean += regionWeight[r] * sol.regionFactor[r].array().log().matrix();
          weight += regionWeight[r];
        }
        // light of given radiance sets every channel's scale: no gauge; a pinned light sets the
        // colour, the guesses the level (one scale over the channels); else one scale per channel
        if (weight > 0 && !givenScale) {
          Vec3d g = (logMean / weight).array().exp().matrix();
          if (options.pinnedLightSetsColour && pinnedScale()) g.setConstant(std::cbrt(g.prod()));
          for (Vec3d& f : sol.regionFactor) f = f.cwiseQuotient(g);
        }
      }
      sol.alternations = it + 1;
      const double r = residual();
      if (std::abs(previous - r) <= options.tolerance * std::max(r, 1e-30)) break;
      previous = r;
    }
    // drop lights that add nothing (zero) or almost nothing to the model's energy
    double energyAll = 0;
    std::vector<double> energy(lights, 0.0);
    for (const Samples& s : data)
      for (int k : active)
        for (int i = 0; i < s.count; ++i)
          for (int c = 0; c < 3; ++c)
            energy[k] += factor(s.region[i], c) * sol.intensity[k][c] * s.light[k][3 * i + c];
    for (int k : active) energyAll += energy[k];
    for (const Samples& s : data)  // the given light's share counts in the whole
      for (int i = 0; i < s.count; ++i)
        for (int c = 0; c < 3; ++c) energyAll += factor(s.region[i], c) * s.given[3 * i + c];
    std::vector<int> keep;
    for (int k : active) {
      const bool zero = sol.intensity[k].maxCoeff() <= 0;
      if (zero || (energyAll > 0 && energy[k] < options.dropShare * energyAll)) {
        sol.dropped[k] = true;
        sol.intensity[k].setZero();
      } else {
        keep.push_back(k);
      }
    }
    if (keep.size() == active.size()) break;
    active = keep;
    if (active.empty()) break;
  }
  sol.residualRms = residual();
  return sol;
}

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
  return solveSamples(data, direct, lights, total, options);
}

}  // namespace ps::lighting
