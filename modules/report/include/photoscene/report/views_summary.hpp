// The views of a twin output folder and the view each part was fitted in: for `photoscene
// check OUT` (text) and report.html (a table).
//
//   const ps::report::ViewsSummary s = ps::report::summarizeViews("OUT");
//   std::fputs(ps::report::viewsText(s).c_str(), stdout);
//
// Read from OUT/scene.json (views), OUT/lights.json (`exposure`, 1 where absent) and
// OUT/materials/<part>.json (`fit.view`; `fit.views`, the optional per-view scores a run with
// several views records: pixels, mean cosine, appearance agreement, score) and OUT/poses.json (the
// objects the `poses` stage moved onto the views' labels, where it ran).
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
  /// An object of the CAD as the poses stage left it (poses.json `objects[]`).
  struct Object {
    std::string name;
    bool moved = false;
    double shiftCm = 0, yawDeg = 0, scale = 1;
    int pixels = 0;             ///< labelled pixels of its parts, every view
    int before = 0, after = 0;  ///< labelled pixels the render mislabels around it
  };
  std::vector<View> views;
  std::vector<Part> parts;  ///< sorted by name; only parts with a materials file
  std::vector<Object> objects;  ///< in the order they were fitted; empty without poses.json
};

/// Reads the summary. Throws ps::InputError naming the file and key when OUT/scene.json is
/// missing or malformed; a missing lights.json or materials folder only leaves defaults.
ViewsSummary summarizeViews(const std::filesystem::path& outDir);

/// One line per view (index, exposure, image, parts fitted there), then one per part with its
/// view (and with several views, every view's score, the chosen one marked *), then one per
/// object the poses stage fitted.
std::string viewsText(const ViewsSummary& summary);

/// The same as an HTML section (id "view-choice").
std::string viewsHtml(const ViewsSummary& summary);

}  // namespace ps::report
