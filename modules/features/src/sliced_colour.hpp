// Private: the sliced Wasserstein distance between the colour distributions of two masked regions
// of the same mask (texture_loss.hpp's colorSliced group).
//
// The masked pixels' colours are projected on fixed directions of linear RGB (luminance, the three
// channels, three opponent axes), each projection is sorted, and the loss is the mean squared
// difference of the sorted values: per direction the squared 2-Wasserstein distance between the
// two one-dimensional distributions (both regions have the same pixel count, so the k-th smallest
// value of one is matched with the k-th smallest of the other; Rabin et al. 2011, Heitz et al.
// 2021). The colour means and standard deviations match a distribution's first two moments per
// channel; a blue ornament on white and a purple-and-cyan mosaic have the same ones, not the same
// sorted projections. Invariant to where the pixels lie (texture, not alignment).
#pragma once

#include <opencv2/core.hpp>

#include <vector>

namespace ps::features_detail {

/// The projection directions (unit vectors of linear RGB).
const std::vector<cv::Vec3d>& slicedDirections();

/// The photo side: its masked pixels' sorted projections, divided by the normaliser nu.
struct SlicedTarget {
  std::vector<cv::Point> pixels;           // mask pixels, crop coordinates, row-major
  std::vector<std::vector<float>> sorted;  // per direction, ascending, pixels.size() entries
  double nu = 1.0;
};

/// @param crop CV_32FC3 (the photo's crop); @param mask0 CV_32FC1 0 / 1, crop's size.
/// @param noise the photo's pixel noise per channel (standard deviation, linear units): each
///        direction's sorted values are drawn towards their median so that their variance loses
///        the noise's (0: unchanged).
SlicedTarget makeSlicedTarget(const cv::Mat& crop, const cv::Mat& mask0, double nu,
                              const cv::Vec3d& noise);

/// Forward results kept for backward: per direction, the residual of each mask pixel (its
/// projection minus the target value of its rank, both over nu).
struct SlicedState {
  std::vector<std::vector<float>> residual;  // [direction][pixel index in target.pixels]
};

/// The mean over directions of the mean squared residual (0 for an empty mask).
double slicedForward(const cv::Mat& crop, const SlicedTarget& target, SlicedState& state);

/// Adds scale * d loss / d crop to gradCrop (CV_32FC3, crop's size).
void slicedBackward(const SlicedTarget& target, const SlicedState& state, double scale,
                    cv::Mat& gradCrop);

}  // namespace ps::features_detail
