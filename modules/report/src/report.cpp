// writeReport: gather the folder into a ReportData, render it, write report.html
// (report_data.hpp; report_gather.cpp and report_html.cpp).
#include "photoscene/report/report.hpp"

#include "photoscene/core/log.hpp"

#include <cstdlib>

#include "photoscene/core/data_folder.hpp"
#include "photoscene/core/timer.hpp"
#include "photoscene/io/files.hpp"
#include "report_data.hpp"

namespace ps {

namespace fs = std::filesystem;

fs::path defaultViewerDir() {
  if (const char* env = std::getenv("PHOTOSCENE_VIEWER_DIR"))
    if (fs::exists(fs::path(env) / "photoscene-viewer.js")) return env;
#ifdef PS_VIEWER_DIR
  const fs::path buildTree = PS_VIEWER_DIR;
#else
  const fs::path buildTree;
#endif
  // an installed tree's share/photoscene/viewer, else the build tree's (ps::findDataFolder)
  if (const fs::path dir = findDataFolder("viewer", buildTree);
      !dir.empty() && fs::exists(dir / "photoscene-viewer.js"))
    return dir;
  if (!buildTree.empty() && fs::exists(buildTree / "photoscene-viewer.js")) return buildTree;
  return {};
}

ReportSummary writeReport(const fs::path& outDir, const ReportOptions& options) {
  Timer timer;
  ReportSummary summary;
  const report_detail::ReportData data = report_detail::gatherReport(outDir, options, &summary);
  io::writeTextFile(outDir / "report.html", report_detail::renderReportHtml(data, options));
  spdlog::info(
      "report {}: {} views ({} renders, {} diffs written), {} parts, metrics {}, viewer {} "
      "({:.2f}s)",
      (outDir / "report.html").string(), summary.views, summary.rendersFound, summary.diffsWritten,
      summary.parts, summary.metricsFound ? "yes" : "no", summary.viewerWritten ? "yes" : "no",
      timer.seconds());
  return summary;
}

}  // namespace ps
