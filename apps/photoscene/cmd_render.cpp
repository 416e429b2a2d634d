// `photoscene render OUT [--camera CAMERA.json] [--lights LIGHTS.json] [--spp N] -o IMAGE`:
// draws a twin folder from its input views or a given camera (spec section 4).
#include "commands.hpp"

#ifdef PS_HAVE_RAYTRACE
#include <memory>

#include "photoscene/core/parallel.hpp"
#include "photoscene/raytrace/render_twin.hpp"
#endif

namespace ps::app {

void addRenderCommand(CLI::App& root) {
  auto* cmd = root.add_subcommand("render", "Render a twin folder from its views or a given camera");
#ifdef PS_HAVE_RAYTRACE
  struct Args {
    std::string out, camera, lights, output;
    int spp = 128, bounces = 12, diffuseBounces = 6, glossyBounces = 4, width = 0, height = 0, threads = 0;
    uint64_t seed = 0;
    bool denoise = false;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("out", a->out, "Output folder of `photoscene run` (scene.json, lights.json, materials/, textures/)")
      ->required();
  cmd->add_option("-o,--output", a->output, "Image to write: .png (sRGB 8-bit), .exr (linear float), .hdr, .jpg; "
                                            "several input views are written as NAME_view<i>.EXT")
      ->required();
  cmd->add_option("--camera", a->camera, "CAMERA.json with one camera object (default: every input view)");
  cmd->add_option("--lights", a->lights, "LIGHTS.json in the form of OUT/lights.json: relight the twin");
  cmd->add_option("--spp", a->spp, "Samples per pixel (default 128)")->check(CLI::Range(1, 1 << 20));
  cmd->add_option("--bounces", a->bounces, "Maximum number of bounces (default 12)")->check(CLI::Range(0, 1024));
  cmd->add_option("--diffuse-bounces", a->diffuseBounces, "Maximum diffuse bounces (default 6, as Cycles)")
      ->check(CLI::Range(0, 1024));
  cmd->add_option("--glossy-bounces", a->glossyBounces, "Maximum glossy bounces (default 4, as Cycles)")
      ->check(CLI::Range(0, 1024));
  cmd->add_flag("--denoise", a->denoise,
                "Denoise the render (G-buffer-guided a-trous filter, guides from the render's own "
                "samples): a clean image at a fraction of the samples, slightly biased");
  cmd->add_option("--seed", a->seed, "Random seed (the same seed gives the same image)");
  cmd->add_option("--width", a->width, "Render at this width (with --height; the camera is resized)")
      ->check(CLI::Range(1, 1 << 15));
  cmd->add_option("--height", a->height, "Render at this height (with --width)")->check(CLI::Range(1, 1 << 15));
  cmd->add_option("--threads", a->threads, "Worker threads (default: all cores)")->check(CLI::Range(0, 4096));
  cmd->callback([a] {
    ThreadLimit limit(a->threads);
    TwinRenderRequest req;
    req.twinDir = a->out;
    if (!a->camera.empty()) req.cameraFile = a->camera;
    if (!a->lights.empty()) req.lightsFile = a->lights;
    req.output = a->output;
    req.options.spp = a->spp;
    req.options.maxBounces = a->bounces;
    req.options.maxDiffuseBounces = a->diffuseBounces;
    req.options.maxGlossyBounces = a->glossyBounces;
    req.options.seed = a->seed;
    req.denoise = a->denoise;
    req.width = a->width;
    req.height = a->height;
    renderTwinCommand(req);
  });
#else
  auto out = std::make_shared<std::string>();
  cmd->add_option("out", *out, "Output folder of `photoscene run`")->required();
  cmd->callback([] { throw NotBuiltYet("render: the raytrace module is not part of this build"); });
#endif
}

}  // namespace ps::app
