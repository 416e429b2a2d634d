// photoscene render: the differentiable per-part render layer (paper section 3.3).
//   ps::PartGeometry, ps::preparePartGeometry()   per part and view, once
//   ps::RenderLayerParams, ps::renderLayerForward(), ps::renderLayerBackward()
#pragma once

#include "photoscene/render/render_layer.hpp"
