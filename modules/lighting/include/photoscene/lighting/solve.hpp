// Emitter intensities from photos (paper section 3.4, "globally consistent lighting").
//
// With N emitters (area lights, plus the environment as one more "light") and V views, the
// renderer draws every light alone at unit radiance: I_{v,k}, linear RGB. The photo of view v is
// modelled as
//
//     P_v(p) = e_v * sum_k x_k (.) I_{v,k}(p)          x_k in R^3, x_k >= 0, e_0 = 1
//
// with (.) the per-channel product: 3 x N non-negative coefficients (the paper's 3 x (N + 1)) and
// one exposure per further view. Each channel is a non-negative least-squares problem over the
// usable pixels (where geometry and photo agree, not saturated, not on an emitter); exposures and
// intensities are solved alternately when there are several views. A light whose coefficient
// ends at zero in every channel, or whose share of the rendered energy is below
// `dropShare`, is dropped (its radiance set to 0) and the rest re-solved.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "photoscene/core/math.hpp"

namespace ps::lighting {

/// Non-negative least squares, min ||A x - b||_2 subject to x >= 0 (Lawson and Hanson 1974,
/// active set). Deterministic; returns the solution (zeros where the bound is active).
Eigen::VectorXd nnls(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, int maxIterations = 0);

/// The data of one view.
struct ViewLightData {
  cv::Mat photo;                 ///< CV_32FC3 linear RGB
  cv::Mat mask;                  ///< CV_8UC1: pixels usable for the fit (non-zero)
  std::vector<cv::Mat> perLight; ///< per light, CV_32FC3 render at unit radiance, photo's size
};

struct SolveOptions {
  bool perViewExposure = true;   ///< solve e_v for views 1..V-1 (view 0 is the reference)
  int maxAlternations = 30;
  double tolerance = 1e-7;       ///< relative residual change that ends the alternation
  /// Photo values at or above this (linear) are treated as clipped and left out; 8-bit photos
  /// clip at 1.0.
  double saturation = 0.99;
  int maxSamplesPerView = 40000; ///< usable pixels are subsampled on a fixed grid above this
  double dropShare = 0.002;      ///< drop lights contributing less than this share of energy
  bool IsValid(std::string* error) const;
};

struct LightSolution {
  std::vector<Vec3d> intensity;  ///< per light: the multiplier on its unit-radiance render
  std::vector<double> exposure;  ///< per view (exposure[0] = 1)
  std::vector<bool> dropped;     ///< per light
  double residualRms = 0;        ///< RMS of the model minus the photo over the samples
  double photoRms = 0;           ///< RMS of the photo over the same samples (for scale)
  int samples = 0;
  int alternations = 0;
  std::string summary() const;
};

/// Solves for every light's RGB intensity (and per-view exposure). Throws ps::Exception when no
/// view has a usable pixel or sizes disagree.
LightSolution solveLights(const std::vector<ViewLightData>& views, const SolveOptions& options = {});

}  // namespace ps::lighting
