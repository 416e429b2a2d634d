// Sample: material part masks and their alignment (paper section 3.1).
//
//   ps_sample_align [SCENE.json] [OUT_FOLDER]
//
// Renders the coarse geometry's part ids from view 0 (M_geo), matches the view's label regions
// to parts by IoU (M_photo; pinned regions keep their part), warps each part's geometry buffers
// onto the photo with the bounding-box affine map of Eq. 1 (M_aln), and writes an overlay.
#include <cstdio>
#include <opencv2/imgproc.hpp>

#include "photoscene/align.hpp"
#include "photoscene/core.hpp"
#include "photoscene/io.hpp"
#include "photoscene/raytrace.hpp"
#include "photoscene/scene.hpp"

int main(int argc, char** argv) {
  ps::initLogging(ps::LogLevel::Warn);
  const std::string scenePath = argc > 1 ? argv[1] : PS_SAMPLE_SCENE;
  const std::filesystem::path out = argc > 2 ? argv[2] : "sample-align";
  try {
    const ps::Scene scene = ps::loadScene(scenePath);
    const ps::View& view = scene.views[0];
    // geometry buffers of the coarse CAD as the camera sees it (gray materials: only geometry matters)
    const std::vector<ps::PartMaterial> gray;
    const ps::PathTracer tracer(scene, gray);
    const ps::GBuffer gb = ps::renderGBuffer(tracer, view.camera);
    const auto geo = ps::align::partMasks(gb.partId);

    // M_photo: the label image's regions, pinned by segment_parts or matched by IoU
    cv::Mat labels = view.segments;
    std::map<int, int> pinned = view.segmentParts;
    if (labels.empty()) labels = ps::align::proposeRegions(view.photo, geo, &pinned);
    const ps::align::MatchResult match = ps::align::matchRegions(labels, geo, pinned);

    std::printf("%-16s %8s %8s %6s %8s %8s\n", "part", "M_geo", "M_photo", "IoU", "M_aln", "dropped");
    cv::Mat overlay = view.photo.clone();
    for (const auto& [part, photoMask] : match.photoMasks) {
      if (!geo.count(part)) continue;
      const ps::align::AlignedPart a = ps::align::alignPart(part, geo.at(part), photoMask, {gb.uv, gb.normalShading});
      std::printf("%-16s %8d %8d %6.2f %8d %8d\n", scene.parts[part].name.c_str(), cv::countNonZero(geo.at(part)),
                  a.photoPixels, ps::align::iou(geo.at(part), photoMask), cv::countNonZero(a.mask), a.droppedPixels);
      // outline M_aln in the overlay
      cv::Mat edges;
      cv::morphologyEx(a.mask, edges, cv::MORPH_GRADIENT, cv::Mat());
      overlay.setTo(cv::Scalar(1.0, 0.2, 0.1), edges);
    }
    for (int label : match.unmatched()) std::printf("region %d left unmatched\n", label);
    std::filesystem::create_directories(out);
    ps::io::writeImage(out / "aligned_masks.png", overlay);
    std::printf("wrote %s\n", (out / "aligned_masks.png").string().c_str());
    return 0;
  } catch (const ps::InputError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
}
