// photoscene eval: image metrics (RMSE, PSNR, SSIM, GMSD) in stated color spaces, and the scoring
// of a twin output folder against its case (photos, parts, novel and relit ground truth).
#pragma once

#include "photoscene/eval/metrics.hpp"
#include "photoscene/eval/texture_distance.hpp"
#include "photoscene/eval/twin_evaluation.hpp"
