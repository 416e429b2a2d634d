// photoscene pipeline: every stage of the method in order, cached on disk, into an output folder.
#pragma once

#include "photoscene/pipeline/batch.hpp"
#include "photoscene/pipeline/pipeline.hpp"
#include "photoscene/pipeline/stage_cache.hpp"
