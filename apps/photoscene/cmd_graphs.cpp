// `photoscene graphs`: list the procedural material graphs or render one (spec section 4).
//
//   photoscene graphs --list
//   photoscene graphs --render GRAPH [--size N] [--seed S] -o DIR
//     writes DIR/GRAPH_albedo.png (sRGB), _normal.png (n * 0.5 + 0.5), _roughness.png (linear),
//     _preview.png (the material on a lit sphere, Lambert + GGX), each written to a temporary
//     name and renamed (ps::io::writeImage).
#include "commands.hpp"
#include "photoscene/core.hpp"
#include "photoscene/graph.hpp"
#include "photoscene/io.hpp"

#include <cstdio>
#include <filesystem>
#include <memory>

namespace ps::app {
namespace {

struct GraphsOptions {
  bool list = false;
  std::string render, out, library;
  int size = 512;
  int64_t seed = -1;
};

void run(const GraphsOptions& o) {
  const GraphLibrary lib = GraphLibrary::load(o.library);
  if (o.list) {
    for (const auto& name : lib.names()) {
      const auto& g = lib.get(name);
      std::printf("%-28s %-12s %d\n", name.c_str(), g.category().c_str(), int(g.parameters().size()));
    }
    if (o.render.empty()) return;
  }
  if (o.render.empty()) throw InputError("graphs", "--list / --render", "expected --list or --render GRAPH");
  if (!lib.contains(o.render))
    throw InputError("graphs", "--render", "expected a graph name from `photoscene graphs --list`, got \"" + o.render + "\"");
  if (o.out.empty()) throw InputError("graphs", "-o", "expected an output folder for --render");
  if (o.size < 4 || o.size > 8192 || (o.size & (o.size - 1)))
    throw InputError("graphs", "--size", "expected a power of two in [4, 8192], got " + std::to_string(o.size));
  MaterialGraph g = lib.create(o.render);
  if (o.seed >= 0) g.setValues(g.randomValues(uint64_t(o.seed)));
  const MaterialMaps m = g.evaluate(o.size);
  PreviewOptions po;
  po.size = 512;
  const cv::Mat preview = renderMaterialPreview(m, po);
  std::filesystem::create_directories(o.out);
  const std::string base = (std::filesystem::path(o.out) / o.render).string();
  // io::writeImage writes to a temporary name and renames
  io::WriteOptions srgb, linear;
  linear.encode = io::ColorSpace::Linear;
  io::writeImage(base + "_albedo.png", m.albedo, srgb);
  io::writeImage(base + "_normal.png", cv::Mat(m.normal * 0.5 + cv::Scalar::all(0.5)), linear);
  io::writeImage(base + "_roughness.png", m.roughness, linear);
  io::writeImage(base + "_preview.png", preview, srgb);
  std::printf("%s_{albedo,normal,roughness,preview}.png\n", base.c_str());
}

}  // namespace

void addGraphsCommand(CLI::App& root) {
  auto o = std::make_shared<GraphsOptions>();
  auto* cmd = root.add_subcommand("graphs", "List or render the procedural material graphs");
  cmd->add_flag("--list", o->list, "One line per graph: name, category, parameter count");
  cmd->add_option("--render", o->render, "Render one graph's maps and a lit preview");
  cmd->add_option("--size", o->size, "Map size in pixels (a power of two)")->capture_default_str();
  cmd->add_option("--seed", o->seed, "Random parameter draw (default: the graph's defaults)");
  cmd->add_option("-o,--output", o->out, "Output folder for --render");
  cmd->add_option("--library", o->library,
                  "Graph folder (default: $PHOTOSCENE_GRAPH_LIBRARY or the installed library)");
  cmd->callback([o] { run(*o); });
}

}  // namespace ps::app
