// Graph selection on a scene with known graphs (the bundled sample by default): the G-buffer and
// the alignment as the pipeline's align stage makes them, then each part's graph by the
// photo-frame key (the pipeline before selectForPart) and by selectForPart (texture space,
// shading removed), against the truth in <scene dir>/gt/twin/materials/<part>.json ("graph").
//   ps_bench_select_sample [SCENE.json] [--cache DIR] [--draws N] [--observed N] [--shading S]
//                          [--scales a,b] [--k K] [--category-first 0|1]
#include <cstdio>
#include <cstdlib>
#include <fstream>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "bank_options.hpp"
#include "photoscene/align.hpp"
#include "photoscene/core.hpp"
#include "photoscene/raytrace.hpp"
#include "photoscene/scene.hpp"
#include "photoscene/select.hpp"

namespace fs = std::filesystem;

int main(int argc, char** argv) {
  ps::initLogging(ps::LogLevel::Warn);
  std::string scenePath = PS_SAMPLE_SCENE;
  fs::path cache = "bank-cache";
  ps::ExemplarBankOptions options;
  ps::PartSelectionOptions query;
  fs::path dump;
  CLI::App app{"Graph selection on a scene with known graphs (default: the bundled sample)"};
  app.add_option("scene", scenePath, "scene.json with gt/twin/materials/<part>.json");
  ps::bench::addBankOptions(app, options);
  app.add_option("--k", query.k, "neighbours that vote");
  app.add_option("--category-first", query.categoryFirst, "vote for a category first (0|1)");
  app.add_option("--cache", cache, "bank cache folder");
  app.add_option("--dump", dump, "write each part's prepared texture (PNG, scaled to its mean)");
  CLI11_PARSE(app, argc, argv);
  try {
    const ps::Scene scene = ps::loadScene(scenePath);
    const ps::View& view = scene.views[0];
    const fs::path truthDir = fs::path(scenePath).parent_path() / "gt" / "twin" / "materials";
    const ps::GraphLibrary library = ps::GraphLibrary::load();
    ps::Timer timer;
    bool cached = false;
    const ps::ExemplarBank bank = ps::ExemplarBank::loadOrBuild(library, options, cache, &cached);
    std::printf("bank: %d exemplars, %s in %.1f s\n", bank.rows(), cached ? "loaded" : "built",
                timer.seconds());

    // the pipeline's align stage (align::alignView), at the photo's resolution
    const std::vector<ps::PartMaterial> gray;
    const ps::PathTracer tracer(scene, gray);
    const ps::GBuffer gb = ps::renderGBuffer(tracer, view.camera);
    const ps::align::ViewAlignment aligned =
        ps::align::alignView(view.photo, view.segments, view.segmentParts, gb.partId, gb.coverage);

    std::printf("%-12s %6s  %-22s %-22s %-22s\n", "part", "pixels", "truth", "photo-frame key",
                "selectForPart");
    int total = 0, oldTop1 = 0, newTop1 = 0, oldCat = 0, newCat = 0;
    for (const auto& [part, photoMask] : aligned.photoMask) {
      const cv::Mat& fit = aligned.fitMask.at(part);
      if (cv::countNonZero(photoMask) == 0 || cv::countNonZero(fit) == 0) continue;
      const std::string& name = scene.parts[part].name;
      std::string truth = "?";
      if (std::ifstream f(truthDir / (name + ".json")); f)
        truth = nlohmann::json::parse(f).value("graph", "?");
      const int pixels = cv::countNonZero(photoMask);
      if (ps::isSmallPart(photoMask, view.camera.width(), view.camera.height())) {
        std::printf("%-12s %6d  %-22s %-22s %-22s\n", name.c_str(), pixels, truth.c_str(),
                    "homogeneous", "homogeneous");
        continue;
      }
      cv::Mat partPhoto;
      cv::warpAffine(view.photo, partPhoto, cv::Mat(aligned.warp.at(part)), view.photo.size(),
                     cv::INTER_LINEAR, cv::BORDER_REFLECT);

      const ps::GraphChoice before =
          bank.select(ps::describeTexture(view.photo, photoMask, options), query.k);
      const ps::GraphChoice after =
          ps::selectForPart(bank, partPhoto, fit, gb.uv, cv::Mat(), query);
      if (!dump.empty()) {
        const ps::PartTexture t =
            ps::preparePartTexture(partPhoto, fit, gb.uv, cv::Mat(), options.shadingSigma, query);
        fs::create_directories(dump);
        cv::Mat png;
        const cv::Scalar m = cv::mean(t.image, t.mask);
        t.image.convertTo(png, CV_8UC3, 127.0 / std::max(1e-6, (m[0] + m[1] + m[2]) / 3));
        cv::cvtColor(png, png, cv::COLOR_RGB2BGR);
        cv::imwrite((dump / (name + ".png")).string(), png);
      }
      const std::string truthCat = library.contains(truth) ? library.get(truth).category() : "?";
      ++total;
      oldTop1 += before.graph == truth;
      newTop1 += after.graph == truth;
      oldCat += before.category == truthCat;
      newCat += after.category == truthCat;
      std::printf("%-12s %6d  %-22s %-22s %-22s (then %s)\n", name.c_str(), pixels, truth.c_str(),
                  before.graph.c_str(), after.graph.c_str(),
                  after.votes.size() > 1 ? after.votes[1].graph.c_str() : "-");
    }
    std::printf(
        "textured parts: %d; photo-frame key: %d right (%d category); selectForPart: %d right (%d "
        "category)\n",
        total, oldTop1, oldCat, newTop1, newCat);
    return 0;
  } catch (const ps::InputError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
}
