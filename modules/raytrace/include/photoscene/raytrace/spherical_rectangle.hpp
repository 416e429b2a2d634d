// Moved to the scene module with the lights that use it (photoscene/scene/spherical_rectangle.hpp).
#pragma once

#include "photoscene/scene/spherical_rectangle.hpp"
