// OUT/report.html, built purely from what is in a twin output folder (spec
// ../shared/spec/scene-format.md section 3), so it can be regenerated at any time:
//
//   ps::writeReport("OUT");   // OUT/report.html, OUT/viewer/*, OUT/renders/view<i>_diff.png
//
// What it reads (each optional except scene.json; what is missing is said in the page):
//   OUT/scene.json            views (photo paths relative to OUT, cameras), geometry (part names)
//   OUT/renders/view<i>.png   the twin rendered from input view i
//   OUT/materials/<part>.json graph, category, params, UV transform, fit (view, loss, seconds,
//                             skipped, the optional loss curve `fit.history`: array of numbers,
//                             and `fit.candidates`: the selection's top graphs with their scores)
//   OUT/lights.json           emitters drawn in the viewer, emitter and window parts
//   OUT/textures/*            map thumbnails
//   OUT/metrics.json          per-view / per-part / novel / relit metrics, stage times
//   OUT/twin.gltf + twin.bin  the 3D viewer's scene (exported from the twin when missing)
// What it writes (each atomically):
//   OUT/report.html
//   OUT/renders/view<i>_diff.png  |render - photo| * 4 (linear), sRGB-encoded, when not present
//   OUT/renders/view<i>_photo.png an sRGB copy of a photo browsers cannot show (EXR, HDR)
//   OUT/previews/<graph>.png      each candidate graph at its default parameters on a lit sphere
//                                 (the page's "Graph choice per part": top 5 per part with scores,
//                                 and the scene.json line that forces one, parts.<name>.graph)
//   OUT/viewer/photoscene-viewer.js  three.js + GLTFLoader + OrbitControls as one classic script
//                                    (vendored and bundled at build time; nothing is fetched)
//   OUT/viewer/twin_data.js          twin.gltf with its buffer and images as data URIs, as a
//                                    classic script setting window.__psTwinGltf
// Both the page and the viewer are classic scripts and data URIs, so report.html works opened
// from disk (file://, where browsers block module imports and fetches of local files) and
// served over HTTP (`photoscene view OUT`).
#pragma once

#include <filesystem>
#include <string>

namespace ps {

struct ReportOptions {
  /// Folder holding photoscene-viewer.js (empty: $PHOTOSCENE_VIEWER_DIR, then share/photoscene/
  /// viewer of an installed tree or the build tree, see ps::findDataFolder). Without it the
  /// report has no 3D viewer (and says so).
  std::filesystem::path viewerDir;
  /// Export OUT/twin.gltf from the twin folder when it is missing (needs a loadable twin).
  bool exportGltfIfMissing = true;
  /// Images embedded into viewer/twin_data.js larger than this (either side, pixels) are
  /// downscaled for the viewer; the twin's files are not touched. 0: embed as they are.
  int viewerTextureSize = 512;
  /// Write the 3D viewer files (viewer/) at all.
  bool viewer = true;
  /// Number of parameters listed per part in the table (the rest are in materials/<part>.json).
  int maxParamsPerPart = 8;
  /// Size (pixels) of the candidate graphs' previews, OUT/previews/<graph>.png, written once per
  /// graph; 0: no previews.
  int candidatePreviewSize = 96;
};

/// What writeReport found and wrote.
struct ReportSummary {
  int views = 0, parts = 0;
  int rendersFound = 0, diffsWritten = 0;
  bool metricsFound = false;
  bool viewerWritten = false;  ///< viewer/photoscene-viewer.js and viewer/twin_data.js written
  std::string viewerNote;      ///< why there is no 3D viewer, when there is none
};

/// Writes OUT/report.html (and the files listed above). Throws ps::InputError when OUT/scene.json
/// is missing or malformed; everything else missing is reported in the page, not thrown.
ReportSummary writeReport(const std::filesystem::path& outDir, const ReportOptions& options = {});

/// The folder of the bundled viewer this build found (see ReportOptions::viewerDir); empty when
/// none.
std::filesystem::path defaultViewerDir();

/// `s` with & < > " ' replaced by their HTML entities: safe as element text and as a quoted
/// attribute value.
std::string escapeHtml(const std::string& s);

}  // namespace ps
