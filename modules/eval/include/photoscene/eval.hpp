// photoscene eval: image metrics (RMSE, PSNR, SSIM, GMSD) in stated color spaces.
#pragma once

#include "photoscene/eval/metrics.hpp"
