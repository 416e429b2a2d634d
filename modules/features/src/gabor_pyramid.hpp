// Private: the Gabor pyramid engine behind the descriptor, the loss and the key.
#pragma once

#include "photoscene/features/texture_descriptor.hpp"

#include <opencv2/core.hpp>

#include <vector>

namespace ps::features_detail {

/// Separable complex Gabor kernels for every orientation, and their flips (for adjoints).
struct GaborBank {
  struct Orientation {
    cv::Mat hr, hi, vr, vi;      // 1 x n (h*) and n x 1 (v*), CV_32F
    cv::Mat hrF, hiF, vrF, viF;  // flipped
    bool hiZero = false, viZero = false;
    float dc = 0.0f;  // DC of the real kernel: a -= dc * (envelope * z) makes it zero-mean
  };
  std::vector<Orientation> orient;
  cv::Mat envH, envV;    // Gaussian envelope, 1 x n and n x 1, each summing to 1
  cv::Mat env2H, env2V;  // squared envelope, each summing to 1
  cv::Mat blurH, blurV;  // [1 4 6 4 1] / 16
};
GaborBank makeGaborBank(const TextureDescriptorOptions& options);

/// The mask side: crop, coverage pyramid, normalized statistics weights.
struct MaskPyramid {
  cv::Rect crop;                  // region of the image read, image coordinates
  cv::Mat mask0;                  // CV_32FC1, crop size, 0 / 1
  int count = 0;                  // mask pixels
  std::vector<cv::Mat> weight;    // per level: w_s / sum(w_s), CV_32FC1 (0 where sum is 0)
  std::vector<double> weightSum;  // per level: sum(w_s) * 4^s (level-0 pixels)
  std::vector<cv::Mat> gain;      // per level: 1 / sqrt(max(C2_s, kMinEnergyCoverage)), CV_32FC1
};
/// @throws ps::Exception for an empty mask
MaskPyramid makeMaskPyramid(const cv::Mat& mask, const TextureDescriptorOptions& options,
                            const GaborBank& bank);

/// Forward intermediates, kept for backward.
struct ForwardState {
  cv::Mat rgb;                     // CV_32FC3 crop (a copy)
  std::vector<cv::Mat> z;          // per level, CV_32FC1
  std::vector<cv::Mat> a, b, mag;  // per band (s * K + k)
  std::vector<double> values;      // descriptor, double
};

/// Computes the descriptor of image (full size, CV_32FC3) over pyramid.crop.
void forwardDescriptor(const cv::Mat& image, const MaskPyramid& pyramid, const GaborBank& bank,
                       const TextureDescriptorOptions& options, ForwardState& state,
                       bool keepForBackward);

/// Gradients with respect to intermediates of the forward pass that other statistics (texture_ps)
/// add to the descriptor's: per band d out / d mag (level size; empty = none), per level
/// d out / d z_s (empty = none), and d out / d crop pixels (CV_32FC3 crop size; empty = none).
struct ExtraGradients {
  std::vector<cv::Mat> mag;
  std::vector<cv::Mat> z;
  cv::Mat rgb;
};

/// Given d out / d values (descriptor length; entries may be 0) and optionally the extra
/// gradients, writes d out / d crop pixels (CV_32FC3, crop size) into gradCrop.
void backwardDescriptor(const MaskPyramid& pyramid, const GaborBank& bank,
                        const TextureDescriptorOptions& options, const ForwardState& state,
                        const std::vector<double>& gradValues, cv::Mat& gradCrop,
                        const ExtraGradients* extra = nullptr);

/// The pyramid's downsampling (blur, even samples) and its adjoint (zero insertion to `size`,
/// blur): expand(m) = 4 * downsampleAdjoint(m, size).
cv::Mat downsample(const cv::Mat& src, const GaborBank& bank);
cv::Mat downsampleAdjoint(const cv::Mat& g, cv::Size size, const GaborBank& bank);

/// Fills a TextureDescriptor from the state.
TextureDescriptor toDescriptor(const ForwardState& state, const MaskPyramid& pyramid,
                               const TextureDescriptorOptions& options);

void checkDescriptorInputs(const cv::Mat& image, const cv::Mat& mask);

}  // namespace ps::features_detail
