// photoscene select: the exemplar bank, the FLANN index, and kNN graph selection.
#pragma once

#include "photoscene/select/exemplar_bank.hpp"
#include "photoscene/select/knn_index.hpp"
#include "photoscene/select/evaluation.hpp"
#include "photoscene/select/part_selection.hpp"
#include "photoscene/select/synthesis.hpp"
