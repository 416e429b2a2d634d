// photoscene lighting: emitter intensities and exposures by non-negative least squares.
#pragma once

#include "photoscene/lighting/solve.hpp"
