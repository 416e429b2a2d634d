// The views of a twin output folder and the view each part was fitted in: for `photoscene
// check OUT` (text) and report.html (a table).
//
//   const ps::report::ViewsSummary s = ps::report::summarizeViews("OUT");
//   std::fputs(ps::report::viewsText(s).c_str(), stdout);
//
// Read from OUT/scene.json (views), OUT/lights.json (`exposure`, 1 where absent) and
// OUT/materials/<part>.json (`fit.view`; `fit.views`, the optional per-view scores a run with
// several views records: pixels, mean cosine, appearance agreement, score).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace ps::report {

struct ViewsSummary {
  struct View {
    int index = 0;
    std::string image;    ///< as scene.json names it
    double exposure = 1;  ///< lights.json exposure[index]
    int parts = 0;        ///< parts fitted in this view
  };
  struct Seen {
    int view = 0;
    int pixels = 0;
    double meanCosine = 0, agreement = 1, score = 0;
    /// of the other views' M_aln points this view sees on the part, the share in its M_aln
    /// (materials fit.views[].mask_consistency); -1: not recorded or none seen
    double maskConsistency = -1;
  };
  struct Part {
    std::string part;
    int view = -1;           ///< fit.view; -1: not fitted
    std::vector<Seen> seen;  ///< fit.views (empty with one view)
  };
  std::vector<View> views;
  std::vector<Part> parts;  ///< sorted by name; only parts with a materials file
};

/// Reads the summary. Throws ps::InputError naming the file and key when OUT/scene.json is
/// missing or malformed; a missing lights.json or materials folder only leaves defaults.
ViewsSummary summarizeViews(const std::filesystem::path& outDir);

/// One line per view (index, exposure, image, parts fitted there), then one per part with its
/// view (and with several views, every view's score, the chosen one marked *).
std::string viewsText(const ViewsSummary& summary);

/// The same as an HTML section (id "view-choice").
std::string viewsHtml(const ViewsSummary& summary);

}  // namespace ps::report
