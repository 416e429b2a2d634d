// Sample: choosing a procedural graph for every part by kNN over the exemplar bank (section 3.2).
//
//   ps_sample_select [SCENE.json] [CACHE_FOLDER]
//
// The bank (every library graph x random draws, rendered canonically, described by the
// lighting-invariant texture key) is built once and cached; each part large enough to show
// texture gets the graph its 21 nearest exemplars vote for; small or thin parts get the
// homogeneous one.
#include <cstdio>

#include "photoscene/core.hpp"
#include "photoscene/features.hpp"
#include "photoscene/select.hpp"
#include "photoscene/scene.hpp"

int main(int argc, char** argv) {
  ps::initLogging(ps::LogLevel::Warn);
  const std::string scenePath = argc > 1 ? argv[1] : PS_SAMPLE_SCENE;
  const std::filesystem::path cache = argc > 2 ? argv[2] : "photoscene-cache";
  try {
    const ps::Scene scene = ps::loadScene(scenePath);
    const ps::View& view = scene.views[0];
    const ps::GraphLibrary library = ps::GraphLibrary::load();
    bool cached = false;
    ps::Timer timer;
    const ps::ExemplarBank bank = ps::ExemplarBank::loadOrBuild(library, {}, cache, &cached);
    std::printf("exemplar bank: %d exemplars, %s in %.2f s\n", bank.rows(), cached ? "loaded" : "built",
                timer.seconds());
    const int minPixels = ps::homogeneousThreshold(view.camera.width(), view.camera.height());
    std::printf("%-16s %7s  %-26s %-10s %s\n", "part", "pixels", "graph", "category", "runner-up");
    for (const auto& [label, part] : view.segmentParts) {
      const cv::Mat mask = view.segments == label;
      const int pixels = cv::countNonZero(mask);
      if (pixels == 0) continue;
      // small or thin: too few pixels whose texture window lies inside the part
      if (ps::isSmallPart(mask, view.camera.width(), view.camera.height())) {
        std::printf("%-16s %7d  %-26s %-10s (interior below %d px)\n",
                    scene.parts[part].name.c_str(), pixels, "homogeneous", "homogeneous",
                    minPixels);
        continue;
      }
      const ps::GraphChoice c = ps::selectForPart(bank, view.photo, mask, cv::Mat());  // no UVs here: photo frame
      const std::string runnerUp = c.votes.size() > 1 ? c.votes[1].graph : "-";
      std::printf("%-16s %7d  %-26s %-10s %s\n", scene.parts[part].name.c_str(), pixels, c.graph.c_str(),
                  c.category.c_str(), runnerUp.c_str());
    }
    return 0;
  } catch (const ps::InputError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
}
