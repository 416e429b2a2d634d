// photoscene report: OUT/report.html (photo / render / difference per view, an interactive
// three.js viewer of OUT/twin.gltf, the per-part table, metrics, loss curves) and a small static
// file server for `photoscene view`.
#pragma once

#include "photoscene/report/report.hpp"
#include "photoscene/report/static_file_server.hpp"
#include "photoscene/report/views_summary.hpp"
