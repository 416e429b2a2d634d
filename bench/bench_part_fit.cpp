// Run time against error of the per-part material fit: synthetic parts (graphs x lightings) fitted
// with each preset; prints a table (time per part, texture-feature distance, mean-albedo error,
// UV rotation / scale error against the truth).
//
//   ps_bench_part_fit [presets (comma list, default fast,balanced)] [graphs (default wood_planks,tile_checker)]
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "photoscene/graph.hpp"
#include "photoscene/optim.hpp"
#include "../modules/render/test/synthetic_room.hpp"

using namespace ps;
using namespace ps::testroom;

static std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ',')) out.push_back(item);
  return out;
}

int main(int argc, char** argv) {
  const std::vector<std::string> presets = split(argc > 1 ? argv[1] : "fast,balanced");
  const std::vector<std::string> graphs = split(argc > 2 ? argv[2] : "wood_planks,tile_checker");
  const GraphLibrary lib = GraphLibrary::load();
  std::printf("| graph | light | preset | seconds | iterations | candidates | texture loss start -> end | at truth | mean albedo err | rot err (deg, mod 180) | mod 90 | scale ratio |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const std::string& gname : graphs)
    for (float light : {12.0f, 30.0f}) {
      MaterialGraph truth = lib.create(gname);
      std::vector<float> v = truth.randomValues(21, 0.35f);
      const std::vector<float> d = truth.defaultValues();
      const std::vector<uint8_t> diff = truth.differentiableMask();
      for (size_t i = 0; i < v.size(); ++i)
        if (!diff[i]) v[i] = d[i];
      truth.setValues(v);
      UvParams uvTrue;
      uvTrue.rotation = radians(35.0f);
      uvTrue.logScale = std::log(0.35f);
      uvTrue.offset = Vec2f(0.1f, 0.3f);
      Room room = makeRoom(160, 120, light);
      std::vector<PartMaterial> mats = {lambert("floor", 0.5f), lambert("walls", 0.7f), lambert("ceiling", 0.8f),
                                        lambert("box", 0.6f)};
      const MaterialMaps tm = truth.evaluate(256, MapSet::of({MapKind::Albedo, MapKind::Normal, MapKind::Roughness}));
      PartMaterial& m = mats[room.floor];
      m.albedoMap = FloatTexture(tm.albedo);
      m.normalMap = FloatTexture(tm.normal);
      m.roughnessMap = FloatTexture(tm.roughness);
      m.specular = 0.5f;  // the layer's default: the truth is a dielectric with the graph's roughness map
      m.uv = uvTrue.toTransform();
      const PathTracer tracer(room.scene, mats);
      RenderOptions ro;
      ro.spp = 256;
      ro.seed = 3;
      ro.filter = PixelFilter::Box;
      ro.filterWidth = 1.0f;
      const cv::Mat photo = tracer.render(room.camera, ro);
      const testroom::View view = prepareView(tracer, room.camera, 8, 8, 9);
      const PartGeometry geo = preparePartGeometry(view.gbuffer, room.camera.position().cast<float>(), view.grid,
                                                   view.gbuffer.mask[room.floor], room.floor);
      const TextureLossTarget target(photo, view.gbuffer.mask[room.floor]);
      for (const std::string& preset : presets) {
        PartFitOptions o = PartFitOptions::preset(preset);
        PartFitOptions z = o;
        z.maxIterations = 0;
        const PartFitResult atTruth = fitPart(truth, geo, photo, target, z, uvTrue);
        const PartFitResult r = fitPart(lib.get(gname), geo, photo, target, o);
        MaterialGraph fitted = lib.create(gname);
        fitted.setValues(r.values);
        const cv::Scalar mf = cv::mean(fitted.evaluate(256, MapSet::of({MapKind::Albedo})).albedo), mt = cv::mean(tm.albedo);
        const double aerr = std::max({std::abs(mf[0] - mt[0]), std::abs(mf[1] - mt[1]), std::abs(mf[2] - mt[2])});
        double rot = degrees(r.uv.rotation - uvTrue.rotation);
        rot = std::fmod(std::fmod(rot, 180.0) + 270.0, 180.0) - 90.0;
        const double rot90 = std::fmod(std::fmod(rot, 90.0) + 135.0, 90.0) - 45.0;  // square tiles
        std::printf("| %s | %.0f | %s | %.1f | %d | %d | %.4f -> %.4f | %.4f | %.3f | %.1f | %.1f | %.3f |\n", gname.c_str(), light,
                    preset.c_str(), r.seconds, r.iterations, r.candidates, r.initialTextureLoss, r.lossTexture,
                    atTruth.initialTextureLoss, aerr, rot, rot90, std::exp(r.uv.logScale - uvTrue.logScale));
        std::fflush(stdout);
      }
    }
  return 0;
}
