// `photoscene check SCENE.json`: validates a scene the way `run` does and prints what it holds.
// `photoscene check OUT`: the same for a twin output folder (its scene.json, lights.json and
// materials, as `render` loads them), then its views with their exposures and the view each part
// was fitted in. (Not in the spec's list: an added subcommand; it writes nothing.)
#include <fmt/format.h>

#include "commands.hpp"
#include "photoscene/align/pose.hpp"
#include "photoscene/core/memory.hpp"
#include "photoscene/graph/graph_library.hpp"
#include "photoscene/pipeline.hpp"
#include "photoscene/report/views_summary.hpp"
#include "photoscene/scene.hpp"

namespace ps::app {

namespace {
void printSummary(const Scene& scene) {
  fmt::print("scene      {}\n", scene.desc.file.string());
  fmt::print("geometry   {} ({} triangles, {} parts)\n", scene.desc.geometry.string(),
             scene.mesh.numTriangles(), scene.parts.size());
  for (const Part& p : scene.parts) {
    std::string note;
    if (p.generatedUvTriangles > 0) note = fmt::format("  (UVs generated for {} triangles)", p.generatedUvTriangles);
    // what scene.json's `parts` asks of it
    if (const auto it = scene.desc.parts.find(p.name); it != scene.desc.parts.end()) {
      const io::PartDesc& d = it->second;
      if (d.graph) note += "  graph " + *d.graph + " (forced)";
      if (d.category) note += "  category " + *d.category + " (given)";
      if (d.fixed) note += "  fixed material";
      if (d.skip) note += "  skipped";
    }
    fmt::print("  part {:<28} {:>7} triangles{}\n", p.name, p.triangleCount, note);
  }
  if (!scene.mesh.objectNames.empty()) {  // what the poses stage may move onto the labels
    std::string movable;
    for (int o : movableObjects(scene))
      movable += (movable.empty() ? "" : ", ") + scene.mesh.objectNames[o];
    fmt::print("objects    {} in the OBJ; movable onto the labels: {}{}\n",
               scene.mesh.objectNames.size(), movable.empty() ? "none" : movable,
               scene.desc.options.refinePoses ? "" : " (off: options.refine_poses is false)");
  }
  for (size_t i = 0; i < scene.views.size(); ++i) {
    const View& v = scene.views[i];
    fmt::print("view {}     {} ({}x{}, f = {:.1f} px), {} in frustum, {}\n", i, v.imagePath.string(),
               v.camera.width(), v.camera.height(), v.camera.fx(),
               countTrianglesInFrustum(scene.mesh, v.camera),
               v.segments.empty() ? std::string("no segments")
                                  : fmt::format("segments with {} pinned regions", v.segmentParts.size()));
  }
  for (const Light* l : scene.lights.all()) {
    if (l->isInfinite())
      fmt::print("{} {}\n", l->type(), l->describe(scene.parts));
    else
      fmt::print("light      {:<12} {}\n", l->label(), l->describe(scene.parts));
  }
}
}  // namespace

void addCheckCommand(CLI::App& root) {
  auto* cmd = root.add_subcommand("check", "Validate a scene.json (and every file it names) and summarize it");
  auto scenePath = std::make_shared<std::string>();
  cmd->add_option("scene", *scenePath, "scene.json, or a twin output folder")->required();
  cmd->callback([scenePath] {
    if (std::filesystem::is_directory(*scenePath)) {
      printSummary(loadTwin(*scenePath).scene);
      fmt::print("{}", report::viewsText(report::summarizeViews(*scenePath)));
    } else {
      const Scene scene = loadScene(*scenePath);
      checkPartSettings(scene.desc, GraphLibrary::load());  // graphs and categories `parts` names
      printSummary(scene);
    }
    fmt::print("peak memory {:.0f} MiB\n", peakMemoryMiB());
  });
}

}  // namespace ps::app
