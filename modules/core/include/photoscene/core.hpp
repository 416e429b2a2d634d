// photoscene core: conventions, errors, logging, progress, parallel loops, seeded RNG, math.
#pragma once

#include "photoscene/core/error.hpp"
#include "photoscene/core/image.hpp"
#include "photoscene/core/interrupt.hpp"
#include "photoscene/core/log.hpp"
#include "photoscene/core/math.hpp"
#include "photoscene/core/parallel.hpp"
#include "photoscene/core/progress.hpp"
#include "photoscene/core/rng.hpp"
#include "photoscene/core/timer.hpp"
