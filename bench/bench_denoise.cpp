// ps_bench_denoise [TWIN] [--reference REF.exr] [--ref-spp N] [--low 16,32] [--high 64,128,256]
//                  [--adaptive 0.05,0.1 --adaptive-spp 32] [--width W --height H]
//                  [--png SIDE_BY_SIDE.png]
// The G-buffer-guided denoiser (ps::denoise) against raw path tracing at equal CPU time, on view
// 0 of a twin (default: the bundled sample's ground-truth twin). The reference is a
// --ref-spp render (default 4096, seed 4242) cached in REF.exr (rendered when the file is
// missing; any linear image of the view's size will do, e.g. a Blender ground truth). Rows: raw
// renders at --low and --high spp (seed 1); the --low renders denoised with guides from a
// G-buffer (center rays; variance estimated from the image) and with the render's own guides
// (PathTracer::render's DenoiseGuides: first-hit albedo, normal and depth averaged over the
// pixel's samples, the variance of the pixel's mean), everything counted in the time; with
// --adaptive, renders of at most --adaptive-spp samples stopped per pixel at each threshold
// (RenderOptions::adaptiveThreshold), raw and denoised. Errors: RMSE and SSIM in sRGB 0-255
// (ps::eval, the evaluation's metrics), the view's exposure applied as `photoscene render` does.
// Time: process CPU seconds (wall time is printed too). --png writes crops of noisy | denoised
// (the render's guides) | reference.
#include <time.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "photoscene/core/image.hpp"
#include "photoscene/core/log.hpp"
#include "photoscene/eval/metrics.hpp"
#include "photoscene/io/image_io.hpp"
#include "photoscene/raytrace.hpp"
#include "photoscene/scene.hpp"

namespace fs = std::filesystem;

namespace {

double cpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}
double wallSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

struct Timed {
  double cpu = 0, wall = 0;
};
template <class F>
Timed timed(F&& f) {
  const double c0 = cpuSeconds(), w0 = wallSeconds();
  f();
  return {cpuSeconds() - c0, wallSeconds() - w0};
}

}  // namespace

int main(int argc, char** argv) {
  fs::path twinDir = fs::path(PS_SAMPLE_DIR) / "gt" / "twin";
  fs::path refPath = "/tmp/ps_denoise_reference.exr";
  fs::path pngPath;
  int refSpp = 4096, width = 320, height = 240;
  std::vector<int> low = {8, 16, 32}, high = {64, 128, 256};
  std::vector<double> adaptive;  // thresholds (RenderOptions::adaptiveThreshold)
  int adaptiveSpp = 32;
  CLI::App app{"The G-buffer-guided denoiser against raw path tracing at equal CPU time"};
  app.add_option("twin", twinDir, "twin folder (default: the bundled sample's ground truth)");
  app.add_option("--reference", refPath, "reference image (rendered at --ref-spp when missing)");
  app.add_option("--ref-spp", refSpp, "samples per pixel of the reference");
  app.add_option("--low", low, "denoised sample counts, comma-separated")->delimiter(',');
  app.add_option("--high", high, "raw sample counts, comma-separated")->delimiter(',');
  app.add_option("--adaptive", adaptive, "adaptive thresholds, comma-separated")->delimiter(',');
  app.add_option("--adaptive-spp", adaptiveSpp, "most samples of an adaptive render");
  app.add_option("--width", width, "render width");
  app.add_option("--height", height, "render height");
  app.add_option("--png", pngPath, "crops of noisy | denoised | reference");
  CLI11_PARSE(app, argc, argv);
  try {
    ps::setLogLevel(ps::LogLevel::Warn);
    const ps::Twin twin = ps::loadTwin(twinDir);
    const ps::PathTracer tracer(twin.scene, twin.materials);
    const ps::Camera cam = twin.scene.views.at(0).camera.resized(width, height);
    const double exposure = twin.exposure.empty() ? 1.0 : twin.exposure[0];
    auto render = [&](int spp, uint64_t seed, ps::DenoiseGuides* guides, double threshold = 0,
                      ps::RenderStats* stats = nullptr) {
      ps::RenderOptions o;
      o.spp = spp;
      o.seed = seed;
      o.adaptiveThreshold = static_cast<float>(threshold);
      o.adaptiveMinSpp = std::max(2, std::min(8, spp / 4));
      cv::Mat img = tracer.render(cam, o, stats, guides);
      if (guides) guides->variance *= exposure * exposure;
      return cv::Mat(img * exposure);
    };

    cv::Mat ref;
    if (fs::exists(refPath)) {
      ref = ps::io::readImage(refPath, ps::io::ColorSpace::Linear);
      if (ref.size() != cv::Size(width, height)) {
        std::fprintf(stderr, "%s: %dx%d, expected %dx%d (delete it to re-render)\n",
                     refPath.c_str(), ref.cols, ref.rows, width, height);
        return 2;
      }
      std::printf("reference: %s (cached)\n", refPath.c_str());
    } else {
      Timed t = timed([&] { ref = render(refSpp, 4242, nullptr); });
      ps::io::writeImage(refPath, ref);
      std::printf("reference: %s, %d spp, %.1f CPU-s (%.1f s wall)\n", refPath.c_str(), refSpp,
                  t.cpu, t.wall);
    }

    using ps::eval::ColorSpace;
    std::printf("\n%dx%d, view 0 of %s; errors against %s, sRGB 0-255\n\n", width, height,
                twinDir.c_str(), refPath.c_str());
    std::printf("| image | CPU-s (render + G-buffer + denoise) | wall s | RMSE | SSIM |\n");
    std::printf("| --- | --- | --- | --- | --- |\n");
    cv::Mat firstNoisy, firstDenoised;
    for (int spp : low) {
      cv::Mat noisy, clean, clean2;
      ps::GBuffer gb;
      ps::DenoiseGuides g, own;
      const Timed tr = timed([&] { noisy = render(spp, 1, nullptr); });
      const Timed tg = timed([&] {
        ps::GBufferOptions go;
        go.coverageSamples = 1;
        go.passWindows = true;
        gb = ps::renderGBuffer(tracer, cam, go);
        g = ps::denoiseGuides(tracer, gb);
      });
      const Timed td = timed([&] { clean = ps::denoise(g, noisy); });
      // the render's own guides (same seed: the same image) and the denoiser on them
      cv::Mat noisy2;
      const Timed tr2 = timed([&] { noisy2 = render(spp, 1, &own); });
      const Timed td2 = timed([&] { clean2 = ps::denoise(own, noisy2); });
      std::printf("| raw %d spp | %.2f | %.2f | %.2f | %.4f |\n", spp, tr.cpu, tr.wall,
                  ps::eval::rmse(noisy, ref, ColorSpace::Srgb255),
                  ps::eval::ssim(noisy, ref, ColorSpace::Srgb255));
      std::printf("| denoised %d spp, G-buffer guides | %.2f (%.2f + %.2f + %.2f) | %.2f | %.2f | %.4f |\n", spp,
                  tr.cpu + tg.cpu + td.cpu, tr.cpu, tg.cpu, td.cpu, tr.wall + tg.wall + td.wall,
                  ps::eval::rmse(clean, ref, ColorSpace::Srgb255),
                  ps::eval::ssim(clean, ref, ColorSpace::Srgb255));
      std::printf("| **denoised %d spp, the render's guides** | %.2f (%.2f + %.2f) | %.2f | %.2f | %.4f |\n", spp,
                  tr2.cpu + td2.cpu, tr2.cpu, td2.cpu, tr2.wall + td2.wall,
                  ps::eval::rmse(clean2, ref, ColorSpace::Srgb255),
                  ps::eval::ssim(clean2, ref, ColorSpace::Srgb255));
      std::fflush(stdout);
      if (firstNoisy.empty()) {
        firstNoisy = noisy;
        firstDenoised = clean2;
      }
    }
    for (double t : adaptive) {
      cv::Mat noisy, clean;
      ps::DenoiseGuides own;
      ps::RenderStats st;
      const Timed tr = timed([&] { noisy = render(adaptiveSpp, 1, &own, t, &st); });
      const Timed td = timed([&] { clean = ps::denoise(own, noisy); });
      const double mean = double(st.samples) / (double(width) * height);
      std::printf("| adaptive %.3g (%d spp max, %.1f mean) raw | %.2f | %.2f | %.2f | %.4f |\n", t,
                  adaptiveSpp, mean, tr.cpu, tr.wall,
                  ps::eval::rmse(noisy, ref, ColorSpace::Srgb255),
                  ps::eval::ssim(noisy, ref, ColorSpace::Srgb255));
      std::printf("| **adaptive %.3g (%d spp max, %.1f mean) denoised** | %.2f (%.2f + %.2f) | %.2f | %.2f | %.4f |\n",
                  t, adaptiveSpp, mean, tr.cpu + td.cpu, tr.cpu, td.cpu, tr.wall + td.wall,
                  ps::eval::rmse(clean, ref, ColorSpace::Srgb255),
                  ps::eval::ssim(clean, ref, ColorSpace::Srgb255));
      std::fflush(stdout);
    }
    for (int spp : high) {
      cv::Mat img;
      const Timed tr = timed([&] { img = render(spp, 1, nullptr); });
      std::printf("| raw %d spp | %.2f | %.2f | %.2f | %.4f |\n", spp, tr.cpu, tr.wall,
                  ps::eval::rmse(img, ref, ColorSpace::Srgb255),
                  ps::eval::ssim(img, ref, ColorSpace::Srgb255));
      std::fflush(stdout);
    }
    if (!pngPath.empty() && !firstNoisy.empty()) {
      // Full frames side by side, then a 2x nearest-neighbour crop of the center.
      std::vector<cv::Mat> cols = {firstNoisy, firstDenoised, ref};
      cv::Mat row, rowCrop;
      cv::hconcat(cols, row);
      const cv::Rect crop(width / 4, height / 4, width / 2, height / 2);
      std::vector<cv::Mat> crops;
      for (const cv::Mat& m : cols) {
        cv::Mat c;
        cv::resize(m(crop), c, cv::Size(), 2.0, 2.0, cv::INTER_NEAREST);
        crops.push_back(c);
      }
      cv::hconcat(crops, rowCrop);
      cv::Mat both;
      cv::vconcat(row, rowCrop, both);
      cv::Mat srgb = ps::linearToSrgb(both, CV_8U);
      cv::cvtColor(srgb, srgb, cv::COLOR_RGB2BGR);
      cv::imwrite(pngPath.string(), srgb);
      std::printf(
          "\nwrote %s: %d spp noisy | denoised | reference (top: full, bottom: center 2x)\n",
          pngPath.c_str(), low.front());
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
  return 0;
}
