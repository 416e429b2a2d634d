// The summary every finite-difference check of the features module shares: analytic against
// central differences at steps h (`numeric`) and 2h (`numeric2`), whose disagreement measures the
// float round-off of the loss and so sets the floor below which an error is not resolvable.
#pragma once

#include <functional>
#include <vector>

#include <opencv2/core.hpp>

#include "photoscene/features/texture_loss.hpp"

namespace ps {

/// `analytic`, `numeric` and `numeric2` have one entry per checked derivative, in the same order.
TextureLossGradientCheck summarizeGradientCheck(const std::vector<double>& analytic,
                                                const std::vector<double>& numeric,
                                                const std::vector<double>& numeric2);

/// The check of a loss of a CV_32FC3 image against its analytic gradient `grad` (same size and
/// type), on the three channels of each of `pixels`: central differences of `loss` at steps
/// `step` and 2 `step` (the steps as taken in float), on a copy of `image`. Throws when a pixel
/// lies outside the image.
TextureLossGradientCheck checkImageGradient(const cv::Mat& image, const cv::Mat& grad,
                                            const std::vector<cv::Point>& pixels, double step,
                                            const std::function<double(const cv::Mat&)>& loss);

}  // namespace ps
