// The report in two steps: gatherReport reads a twin output folder into a ReportData (and writes
// the derived files the page links: difference images, sRGB copies of photos, candidate graph
// previews, the viewer's scripts); renderReportHtml turns a ReportData into the page, reading no
// file. writeReport (report.cpp) is the two in a row.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "photoscene/io/scene_json.hpp"
#include "photoscene/report/report.hpp"

namespace ps::report_detail {

using nlohmann::json;

/// One input view: its images as URLs relative to the folder (empty: missing) and its metrics.
struct ReportView {
  int index = 0;
  std::string photoUrl, renderUrl, diffUrl;
  std::string note;  ///< why an image is missing
  io::CameraDesc camera;
  json metrics;  ///< metrics.json's views[] entry of this view, or null
};

/// A graph the selection considered for a part (materials/<part>.json fit.candidates).
struct ReportCandidate {
  std::string graph, category;
  double score = 0;
  int votes = 0;
  std::string previewUrl;  ///< previews/<graph>.png (empty: the graph is not in the library)
  bool chosen = false;     ///< the graph the part was fitted with
};

/// A finalist of selection by synthesis (materials fit.finalists): its short fit on the part.
struct ReportFinalist {
  std::string graph;
  double loss = 0;
  double contrast = 0;    ///< typical local contrast of its render (NaN: not recorded)
  double coarseContrast = 0;  ///< the same at 2 x 2 cells (NaN: not recorded)
  double chroma = 0;          ///< chromaticity spread of its render (NaN: not recorded)
  double chromaOutside = 0;   ///< its render's share in colours the photo lacks (NaN: none)
  bool qualifies = true;      ///< passed the pixel-error, contrast and colour tests
  bool chosen = false;
};

/// One part: its materials file as read (an object, possibly empty) and what the page adds.
struct ReportPart {
  std::string name;
  std::string role;  ///< "emitter", "window" or empty
  std::string note;  ///< why the materials file is missing or unreadable
  json material = json::object();
  std::vector<std::pair<std::string, std::string>> mapUrls;  ///< (albedo|normal|..., URL)
  std::vector<ReportCandidate> candidates;                   ///< best first, at most 5
  std::vector<ReportFinalist> finalists;  ///< lowest loss first (select's short fits)
  double photoContrast = 0;               ///< the photo's typical local contrast (NaN: none)
  double photoCoarseContrast = 0;         ///< the same at coarseScale cells (NaN: none)
  double photoChroma = 0;                 ///< the photo's chromaticity spread (NaN: none)
  /// pixels a side of the cells of the coarse contrasts (fit.coarse_contrast_scale)
  int coarseScale = 2;
  std::string textureRejected;  ///< the graph whose full fit was rejected for homogeneous
  std::string categoryGiven;    ///< `parts.<name>.category` of the scene (empty: none)
  json metrics;  ///< metrics.json's parts.<name>, or null
};

/// Everything the page shows.
struct ReportData {
  std::string title;
  std::string preset;       ///< metrics.json's preset, or empty
  double totalSeconds = 0;  ///< metrics.json's total_seconds, or NaN
  std::vector<ReportView> views;
  std::vector<ReportPart> parts;
  std::string partsNote;  ///< where the part names came from, when not the OBJ
  json metrics = json::object();
  std::string metricsNote;        ///< why there are no (or partial) metrics
  json emitters = json::array();  ///< rectangles for the viewer (center, edge_u, edge_v, radiance)
  bool viewerWritten = false;
  std::string viewerNote;
  /// the views, their exposures and each part's view (report::viewsHtml), or empty
  std::string viewChoiceHtml;
  std::string viewChoiceNote;  ///< why it is missing
};

/// Reads `outDir` (see report.hpp for what) into a ReportData, writing the derived files;
/// counts what it found and wrote in `summary`. Throws ps::InputError when scene.json is missing
/// or malformed.
ReportData gatherReport(const std::filesystem::path& outDir, const ReportOptions& options,
                        ReportSummary* summary);

/// The page (report.html's text) for `data`.
std::string renderReportHtml(const ReportData& data, const ReportOptions& options);

// JSON access that tolerates missing keys and wrong types.
/// j[key] when j is an object holding a non-null key, else nullptr.
const json* at(const json& j, const std::string& key);
/// j[k0][k1]... or nullptr.
const json* path(const json& j, std::initializer_list<const char*> keys);
/// The number of a JSON value, or NaN.
double num(const json* j);

}  // namespace ps::report_detail
