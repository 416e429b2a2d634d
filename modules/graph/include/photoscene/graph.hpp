// photoscene graph: procedural material graphs (the material prior of PhotoScene, section 3.2).
//
//   material_graph.hpp  ps::MaterialGraph: parameters, evaluate(), backward(); map conventions
//   graph_library.hpp   ps::GraphLibrary: the folder of JSON graphs, categories, content hash
//   node_catalog.hpp    the node types graph files may use
//   gradient_check.hpp  finite-difference gradient checks of graphs and node types
//   palette_prior.hpp   the fit's prior that keeps a colour ramp's hues together
//   preview.hpp         lit sphere / plane previews (Lambert + GGX)
#pragma once

#include "photoscene/graph/gradient_check.hpp"
#include "photoscene/graph/graph_library.hpp"
#include "photoscene/graph/material_graph.hpp"
#include "photoscene/graph/node_catalog.hpp"
#include "photoscene/graph/palette_prior.hpp"
#include "photoscene/graph/preview.hpp"
