// photoscene raytrace: Embree BVH, G-buffers, a path tracer (area + environment lights,
// Lambert + GGX, NEE + MIS), one-light-at-a-time images, incident-light grids, twin rendering.
#pragma once

#include "photoscene/raytrace/accel.hpp"
#include "photoscene/raytrace/bsdf.hpp"
#include "photoscene/raytrace/denoise.hpp"
#include "photoscene/raytrace/gbuffer.hpp"
#include "photoscene/raytrace/incident_light.hpp"
#include "photoscene/raytrace/path_tracer.hpp"
#include "photoscene/raytrace/render_twin.hpp"
