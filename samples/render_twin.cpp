// Sample: render a twin folder (materials/*.json, textures/, lights.json, scene.json) from its
// input view with the path tracer, as `photoscene render` does.
//
//   ps_sample_render [TWIN_FOLDER] [OUT.png]
#include <cstdio>

#include "photoscene/core.hpp"
#include "photoscene/io.hpp"
#include "photoscene/raytrace.hpp"
#include "photoscene/scene.hpp"

int main(int argc, char** argv) {
  ps::initLogging(ps::LogLevel::Warn);
  const std::string twinPath = argc > 1 ? argv[1] : PS_SAMPLE_TWIN;
  const std::string outPath = argc > 2 ? argv[2] : "sample-render.png";
  try {
    const ps::Twin twin = ps::loadTwin(twinPath);
    const ps::PathTracer tracer(twin.scene, twin.materials);
    ps::RenderOptions options;
    options.spp = 32;
    ps::RenderStats stats;
    const cv::Mat image = tracer.render(twin.scene.views[0].camera, options, &stats);
    ps::io::writeImage(outPath, image);
    std::printf("rendered %dx%d at %d spp in %.2f s (%.1f M rays/s); wrote %s\n", image.cols, image.rows,
                options.spp, stats.seconds, stats.raysPerSecond() / 1e6, outPath.c_str());
    return 0;
  } catch (const ps::InputError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
}
