// photoscene align: part masks, IoU matching, the bounding-box warp of Eq. (1), texture
// unwarping and view choice.
#pragma once

#include "photoscene/align/align.hpp"
#include "photoscene/align/pose.hpp"
#include "photoscene/align/view_alignment.hpp"
