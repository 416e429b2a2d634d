// `photoscene eval OUT --scene SCENE.json [--spp N]`: recompute OUT/metrics.json against the
// photos and any ground-truth renders of the case (spec section 4; ps::eval::evaluateTwin).
#include "commands.hpp"

#ifdef PS_HAVE_EVAL
#include <fmt/format.h>

#include <cmath>
#include <iostream>
#include <memory>

#include "photoscene/core/parallel.hpp"
#include "photoscene/eval/twin_evaluation.hpp"
#else
#include "photoscene/scene.hpp"
#endif

namespace ps::app {

#ifdef PS_HAVE_EVAL
namespace {

std::string num(double v, int digits) {
  return std::isfinite(v) ? fmt::format("{:.{}f}", v, digits) : "-";
}

std::string row(const std::string& name, const eval::ImageScore& s) {
  return fmt::format("| {} | {} | {} | {} | {} | {} | {} |", name, num(s.srgb255.rmse, 2),
                     num(s.srgb255.psnr, 2), num(s.srgb255.ssim, 4), num(s.srgb255.gmsd, 4),
                     num(s.linear.rmse, 4), num(s.linear.psnr, 2));
}

void printTable(const eval::TwinEvaluation& e) {
  std::cout << "| image | RMSE srgb255 | PSNR srgb255 | SSIM srgb255 | GMSD srgb255 | RMSE linear "
               "| PSNR linear |\n"
               "| --- | --- | --- | --- | --- | --- | --- |\n";
  for (const auto& v : e.views)
    std::cout << row("view" + std::to_string(v.view) + " (" + v.image + ")", v.score) << "\n";
  for (const auto& g : e.novel) std::cout << row(g.name, g.score) << "\n";
  for (const auto& g : e.relit) std::cout << row(g.name, g.score) << "\n";
  if (!e.parts.empty()) {
    std::cout << "\n| part | view | M_aln pixels | RMSE srgb255 | RMSE linear |\n| --- | --- | --- "
                 "| --- | --- |\n";
    for (const auto& p : e.parts)
      std::cout << fmt::format("| {} | {} | {} | {} | {} |\n", p.part, p.view, p.pixels,
                               num(p.rmseSrgb255, 2), num(p.rmseLinear, 4));
  }
  for (const auto& n : e.notes) std::cout << "note: " << n << "\n";
  std::cout.flush();
}

}  // namespace
#endif

void addEvalCommand(CLI::App& root) {
  struct Args {
    std::string out, scene;
    int spp = 64, threads = 0;
    uint64_t seed = 0;
    bool noParts = false, noGroundTruth = false, rerender = false, noDenoise = false;
  };
  auto a = std::make_shared<Args>();
  auto* cmd = addOutFolderCommand(
      root, "eval", "Recompute metrics.json of an output folder against the photos", a->out);
  cmd->add_option("--scene", a->scene,
                  "scene.json with the photos (its folder's gt/ renders are scored too)")
      ->required();
#ifdef PS_HAVE_EVAL
  cmd->add_option("--spp", a->spp, "Samples per pixel of the renders made for scoring (default 64)")
      ->check(CLI::Range(1, 1 << 16));
  cmd->add_option("--seed", a->seed, "Path tracer seed");
  cmd->add_option("--threads", a->threads, "Worker threads (default: all cores)")
      ->check(CLI::Range(0, 4096));
  cmd->add_flag("--rerender", a->rerender,
                "Render the input views even when OUT/renders/view<i>.exr exist");
  cmd->add_flag("--no-denoise", a->noDenoise,
                "Score the renders made here as path traced (default: denoised, as `run` does)");
  cmd->add_flag("--no-parts", a->noParts, "Skip the per-part RMSE over the aligned masks");
  cmd->add_flag("--no-ground-truth", a->noGroundTruth,
                "Skip the case's novel-view and relit ground truth");
  cmd->callback([a] {
    ThreadLimit limit(a->threads);
    eval::EvalOptions opt;
    opt.spp = a->spp;
    opt.seed = a->seed;
    opt.useSavedRenders = !a->rerender;
    opt.parts = !a->noParts;
    opt.groundTruth = !a->noGroundTruth;
    opt.denoise = !a->noDenoise;
    const eval::TwinEvaluation e = eval::evaluateTwin(a->out, a->scene, opt);
    eval::writeMetricsJson(a->out, e);
    printTable(e);
  });
#else
  cmd->callback([a] {
    loadScene(a->scene);  // bad input first: exit 2
    throw NotBuiltYet("eval: the eval module is not part of this build");
  });
#endif
}

}  // namespace ps::app
