// photoscene optim: Adam over parameter vectors, early stopping, and the per-part material fit.
#pragma once

#include "photoscene/optim/adam.hpp"
#include "photoscene/optim/homogeneous_fit.hpp"
#include "photoscene/optim/part_fit.hpp"
#include "photoscene/optim/roughness_prior.hpp"
#include "photoscene/optim/uv_spectrum.hpp"
