// The pipeline with several photos of one room: a synthetic case made here from the bundled
// sample's geometry and lights with one known albedo per part (three views, each at its own
// exposure), and the same case with one view's photo twice as bright.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>
#include <set>

#include "photoscene/align.hpp"
#include "photoscene/core.hpp"
#include "photoscene/core/color.hpp"
#include "photoscene/io.hpp"
#include "photoscene/pipeline.hpp"
#include "photoscene/raytrace.hpp"
#include "photoscene/report.hpp"
#include "photoscene/scene.hpp"
#include "sample_paths.hpp"
#include "shared_run.hpp"

namespace ps {
namespace {

namespace fs = std::filesystem;

using test::kSample;

constexpr int kWidth = 160, kHeight = 120;

/// The cameras of the synthetic case: the sample's view 0, its novel view, and one from the door.
std::vector<io::CameraDesc> cameras() {
  return {io::lookAtCamera(kWidth, kHeight, 62, Vec3d(-2.1, 1.55, 1.75), Vec3d(0.4, 0.55, -1.3)),
          io::lookAtCamera(kWidth, kHeight, 58, Vec3d(2.0, 1.4, 1.6), Vec3d(-0.8, 0.5, -1.2)),
          io::lookAtCamera(kWidth, kHeight, 60, Vec3d(0.3, 1.7, 1.9), Vec3d(-0.3, 0.3, -1.5))};
}

/// The true albedo of part `id`: distinct colours from dark to light.
Vec3f trueAlbedo(int id) {
  static const Vec3f palette[] = {
      {0.55f, 0.45f, 0.35f}, {0.80f, 0.80f, 0.78f}, {0.60f, 0.62f, 0.55f}, {0.50f, 0.55f, 0.65f},
      {0.70f, 0.40f, 0.30f}, {0.35f, 0.50f, 0.40f}, {0.25f, 0.30f, 0.50f}, {0.45f, 0.20f, 0.20f},
      {0.65f, 0.55f, 0.35f}, {0.30f, 0.30f, 0.30f}, {0.75f, 0.65f, 0.55f}};
  return palette[id % 11];
}

/// A label image as a segmentation would give it: 1000 + part id wherever the G-buffer shows a
/// part, 0 elsewhere (CV_32SC1), and each label's part name.
struct Labels {
  cv::Mat image;
  std::map<int, std::string> parts;
};

Labels labelsOf(const GBuffer& gb, const Scene& scene) {
  Labels l;
  l.image = cv::Mat(gb.partId.size(), CV_32SC1, cv::Scalar(0));
  for (int y = 0; y < l.image.rows; ++y)
    for (int x = 0; x < l.image.cols; ++x)
      if (const int p = gb.partId.at<int>(y, x); p >= 0) {
        l.image.at<int>(y, x) = 1000 + p;
        l.parts[1000 + p] = scene.parts[p].name;
      }
  return l;
}

/// What the synthetic case varies.
struct CaseSpec {
  std::vector<double> exposure;  ///< per view: the photo is the render times this
  /// multiplies every light's radiance in the photos (not in scene.json, whose lights are fitted)
  Vec3f tint = Vec3f(1, 1, 1);
  std::set<std::string> fixed;  ///< parts given in scene.json with their true material
  bool givenLights = false;     ///< scene.json gives the lights' true radiance (times `tint`)
  /// scene.json's geometry is the one the photos were rendered from (room_exact.obj), not the
  /// coarse one (room.obj: furniture moved, turned and scaled as coarse CAD would be)
  bool exactGeometry = false;
};

/// Renders the sample's exact geometry and lights, every part homogeneous (trueAlbedo, roughness
/// 0.8), from every camera, times the view's exposure, as linear EXR photos with label images,
/// and writes DIR/scene.json with the two ceiling lights to fit and every part's graph
/// `homogeneous` (the fit in closed form: what is tested is the exposure), as `spec` says.
void makeCase(const fs::path& dir, const CaseSpec& spec) {
  fs::create_directories(dir / "photos");
  fs::create_directories(dir / "segments");
  Twin twin = loadTwin(kSample / "gt/twin");
  for (Light* l : twin.scene.lights.all())
    if (const std::optional<Vec3f> s = l->scale()) l->setScale(s->cwiseProduct(spec.tint));
  std::vector<PartMaterial> materials;
  for (const Part& p : twin.scene.parts) {
    PartMaterial m = PartMaterial::defaultGray(p.name);
    m.albedo = trueAlbedo(p.id);
    m.roughness = 0.8f;
    materials.push_back(m);
  }
  const PathTracer tracer(twin.scene, materials);
  RenderOptions ro;
  ro.spp = 64;
  ro.seed = 5;
  nlohmann::json views = nlohmann::json::array();
  const std::vector<io::CameraDesc> cams = cameras();
  for (size_t v = 0; v < cams.size(); ++v) {
    const Camera cam = Camera::fromDesc(cams[v]);
    cv::Mat photo = tracer.render(cam, ro) * spec.exposure[v];
    const std::string name = "view" + std::to_string(v);
    io::writeImage(dir / "photos" / (name + ".exr"), photo);
    const Labels labels = labelsOf(renderGBuffer(tracer, cam), twin.scene);
    cv::Mat png;
    labels.image.convertTo(png, CV_16UC1);
    io::writeRawImage(dir / "segments" / (name + ".png"), png);
    nlohmann::json pinned = nlohmann::json::object();
    for (const auto& [label, part] : labels.parts) pinned[std::to_string(label)] = part;
    views.push_back({{"image", "photos/" + name + ".exr"},
                     {"color_space", "linear"},
                     {"camera", io::cameraToJson(cams[v])},
                     {"segments", "segments/" + name + ".png"},
                     {"segment_parts", pinned}});
  }
  nlohmann::json scene = io::readJsonFile(kSample / "scene.json");
  scene["geometry"] = (kSample / (spec.exactGeometry ? "room_exact.obj" : "room.obj")).string();
  scene["views"] = views;
  if (spec.givenLights) {
    const std::vector<Light*> lights = twin.scene.lights.all();
    ASSERT_EQ(scene["lights"]["area"].size(), lights.size());
    for (size_t k = 0; k < lights.size(); ++k) {
      const Vec3f r = *lights[k]->scale();
      scene["lights"]["area"][k]["radiance"] = {r.x(), r.y(), r.z()};
    }
  }
  for (const Part& p : twin.scene.parts) {
    const Vec3f a = trueAlbedo(p.id);
    if (spec.fixed.count(p.name))
      scene["parts"][p.name]["fixed"] = {{"albedo", {a.x(), a.y(), a.z()}}, {"roughness", 0.8}};
    else
      scene["parts"][p.name]["graph"] = "homogeneous";
  }
  io::writeJsonFile(dir / "scene.json", scene);
}

PipelineOptions caseOptions(const fs::path& dir) {
  PipelineOptions o;
  o.scene = dir / "scene.json";
  o.out = dir / "twin";
  o.preset = "balanced";
  o.textureSize = 64;
  o.workWidth = kWidth;
  o.maxFitIterations = 20;
  o.writeGltf = false;
  o.bankCache = test::kBankCache;
  return o;
}

/// Per fitted part seen well (fit.pixels at least `minPixels`, the fitted view's mean |cos| at
/// least `minCosine`): its albedo, and the view it was fitted in.
std::map<std::string, std::pair<Vec3d, int>> fittedAlbedos(const fs::path& out, int minPixels,
                                                           double minCosine = 0) {
  std::map<std::string, std::pair<Vec3d, int>> albedo;
  for (const auto& e : fs::directory_iterator(out / "materials")) {
    const nlohmann::json m = io::readJsonFile(e.path());
    if (!m["fit"].contains("pixels") || m["fit"]["pixels"].get<int>() < minPixels) continue;
    double cosine = 1;
    for (const auto& v : m["fit"].value("views", nlohmann::json::array()))
      if (v["view"] == m["fit"]["view"]) cosine = v["mean_cosine"].get<double>();
    if (cosine < minCosine) continue;
    const io::MaterialFileDesc d = io::readMaterialJson(e.path());
    albedo[d.part] = {d.homogeneous.albedo, *d.fitView};
  }
  return albedo;
}

// Three views at exposures 1, 0.6 and 1.5, run once; then the same case with view 1's photo
// twice as bright.
class MultiView : public test::SharedRun<MultiView> {
 protected:
  static void SetUpTestSuite() {
    dir_ = std::make_unique<io::TempDir>("ps-multiview");
    makeCase(dir_->path() / "a", {.exposure = {1.0, 0.6, 1.5}, .exactGeometry = true});
    result_ = std::make_unique<PipelineResult>(runPipeline(caseOptions(dir_->path() / "a")));
  }
};

TEST_F(MultiView, recovers_the_exposures_and_the_albedos_within_5_percent) {
  ASSERT_EQ(result_->exposure.size(), 3u);
  EXPECT_DOUBLE_EQ(result_->exposure[0], 1.0);
  EXPECT_NEAR(result_->exposure[1], 0.6, 0.6 * 0.03);
  EXPECT_NEAR(result_->exposure[2], 1.5, 1.5 * 0.03);
  // One scale per channel for all albedos stays open (brighter or warmer lights, darker or cooler
  // materials): the recovered albedos are compared after the median ratio over the parts, their
  // luminance and each channel. The parts compared are those a view sees well (at least 300
  // pixels of M_aln at a mean |cos| of at least 0.3): the ceiling, seen only at grazing angles
  // and lit only by the walls, is left out.
  const Scene scene = loadScene(dir_->path() / "a/scene.json", {.loadPhotos = false});
  const auto got = fittedAlbedos(dir_->path() / "a/twin", 300, 0.3);
  ASSERT_GE(got.size(), 6u);
  const auto truth = [&](const std::string& name) {
    return Vec3d(trueAlbedo(scene.partId(name)).cast<double>());
  };
  const auto median = [](std::vector<double> x) {
    std::sort(x.begin(), x.end());
    return x[x.size() / 2];
  };
  std::vector<double> lum;
  std::vector<double> channel[3];
  for (const auto& [name, a] : got) {
    lum.push_back(luminance(a.first) / luminance(truth(name)));
    for (int c = 0; c < 3; ++c) channel[c].push_back(a.first[c] / truth(name)[c]);
  }
  const double lumScale = median(lum);
  const Vec3d scale(median(channel[0]), median(channel[1]), median(channel[2]));
  std::set<int> views;
  for (const auto& [name, a] : got) {
    const double l = luminance(a.first) / luminance(truth(name)) / lumScale;
    const Vec3d r = a.first.cwiseQuotient(truth(name)).cwiseQuotient(scale);
    std::printf("%-12s view %d  albedo / truth, scaled: luminance %.3f, channels %.3f %.3f %.3f\n",
                name.c_str(), a.second, l, r[0], r[1], r[2]);
    // the luminance within 5 % (the bar): measured within 2.6 % (balanced, 160 x 120)
    // with the lamps sampled in round 1's incident grids (PresetBudget::incident1DirectSamples),
    // which set the final albedos; with path samples alone the sofa was 5.9 % off. A part that
    // took its view's exposure into its albedo would be 40 % or 50 % off. On the coarse geometry
    // (room.obj) the cabinet, whose side faces the camera and takes the lamps' light at a grazing
    // angle, comes out 5.6 % too bright (9.1 % without the lamps sampled): a turn of 1-3 degrees
    // moves its shading that much, whatever the exposure.
    EXPECT_NEAR(l, 1.0, 0.05) << name << " (fitted in view " << a.second << ")";
    // each channel within 8 %: measured within 5.1 % (table_top's red). The two lamps' colours
    // are solved with the albedos (lighting/solve.hpp), and one lamp comes out about 6 % brighter
    // than the other against the truth, which moves the parts each lights most
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(r[c], 1.0, 0.08)
          << name << " channel " << c << " (fitted in view " << a.second << ")";
    views.insert(a.second);
  }
  EXPECT_GE(views.size(), 2u) << "every part was fitted in one view: the case tests nothing";
  // the materials file records how each view sees a part, and how its aligned mask there agrees
  // with the other views' (MultiViewMasks below; here on the exact geometry)
  const nlohmann::json m = io::readJsonFile(dir_->path() / "a/twin/materials/floor.json");
  ASSERT_TRUE(m["fit"].contains("views"));
  EXPECT_GE(m["fit"]["views"].size(), 2u);
  for (const auto& v : m["fit"]["views"]) {
    ASSERT_TRUE(v.contains("mask_consistency")) << v.dump();
    EXPECT_GE(v["mask_consistency"].get<double>(), 0.95) << v.dump();
  }
}

TEST_F(MultiView, one_photo_twice_as_bright_doubles_its_exposure_and_keeps_the_albedos) {
  makeCase(dir_->path() / "b", {.exposure = {1.0, 1.2, 1.5}, .exactGeometry = true});
  const PipelineResult b = runPipeline(caseOptions(dir_->path() / "b"));
  ASSERT_EQ(b.exposure.size(), 3u);
  EXPECT_NEAR(b.exposure[1] / result_->exposure[1], 2.0, 2.0 * 0.02);
  EXPECT_NEAR(b.exposure[2] / result_->exposure[2], 1.0, 0.02);
  const auto pa = fittedAlbedos(dir_->path() / "a/twin", 100);
  const auto pb = fittedAlbedos(dir_->path() / "b/twin", 100);
  ASSERT_EQ(pa.size(), pb.size());
  for (const auto& [name, a] : pa) {
    ASSERT_TRUE(pb.count(name)) << name;
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(pb.at(name).first[c] / a.first[c], 1.0, 0.02)
          << name << " channel " << c << " (fitted in view " << a.second << ")";
  }
}

// Under a warm light, with the walls given (`fixed`): the light solve anchors its colour and
// level on the walls' known albedos, so the fitted albedos are the true ones, colour and level,
// not a neutral light and albedos that carry its warmth at the pinned mean.
TEST(FixedPartsAnchor, a_warm_light_and_the_albedo_level_come_from_the_given_walls) {
  io::TempDir dir("ps-anchor");
  const Vec3f warm(1.0f, 0.72f, 0.45f);
  makeCase(dir.path() / "c", {.exposure = {1.0, 1.0, 1.0},
                              .tint = warm,
                              .fixed = {"wall_back", "wall_left", "wall_right"}});
  PipelineOptions o = caseOptions(dir.path() / "c");
  const PipelineResult r = runPipeline(o);
  const Scene scene = loadScene(dir.path() / "c/scene.json", {.loadPhotos = false});
  const auto got = fittedAlbedos(dir.path() / "c/twin", 300, 0.3);
  ASSERT_GE(got.size(), 3u);
  for (const auto& [name, a] : got) {
    const Vec3d truth = trueAlbedo(scene.partId(name)).cast<double>();
    std::printf("%-12s albedo %.3f %.3f %.3f  truth %.3f %.3f %.3f\n", name.c_str(), a.first[0],
                a.first[1], a.first[2], truth[0], truth[1], truth[2]);
    // the level within 15 %, the colour (each channel against green) within 5 %. The level also
    // carries the roughness, which the photos hardly show (truth 0.8; a homogeneous part takes
    // the prior's centre or what a predicted highlight says, optim/homogeneous_fit.hpp):
    // measured 1-11 % with the roughness by statLoss, 1-13.5 % from highlights and the prior,
    // 0-8.5 % with the lamps sampled in round 1's grids (the cabinet the worst)
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(a.first[c] / truth[c], 1.0, 0.15) << name << " channel " << c;
    for (int c : {0, 2})
      EXPECT_NEAR((a.first[c] / a.first[1]) / (truth[c] / truth[1]), 1.0, 0.05)
          << name << " channel " << c << " against green";
  }
  // the solved lights carry the tint: each channel's ratio to the true radiance times the tint
  // is one number per light (the level), within 5 %
  const nlohmann::json lights = io::readJsonFile(dir.path() / "c/twin/lights.json");
  const nlohmann::json truth = io::readJsonFile(kSample / "gt/twin/lights.json");
  ASSERT_EQ(lights["emitters"].size(), truth["emitters"].size());
  for (size_t k = 0; k < truth["emitters"].size(); ++k) {
    double ratio[3];
    for (int c = 0; c < 3; ++c)
      ratio[c] = lights["emitters"][k]["radiance"][c].get<double>() /
                 (truth["emitters"][k]["radiance"][c].get<double>() * warm[c]);
    EXPECT_NEAR(ratio[1] / ratio[0], 1.0, 0.05) << "light " << k;
    EXPECT_NEAR(ratio[2] / ratio[0], 1.0, 0.05) << "light " << k;
  }
  (void)r;
}

// With the lights given at their true radiance there is no scale to pin: the fitted albedos
// must be the true ones, colour and level. The grids the second refine fits against carry the
// light bounced by the first refine's albedos, which come from grids lit by the neutral guesses
// (photo medians: the light's colour twice); without the bounce stage (stage_bounce.cpp),
// which makes the albedos consistent with the light they bounce themselves, each channel's
// error alternated from round to round and the last one kept it: measured red/green up to
// 14 % off (cabinet 1.138, wall_right 1.114, floor 1.10), with it within 2 %.
TEST(GivenLights, the_fitted_albedos_are_the_true_ones) {
  io::TempDir dir("ps-given-lights");
  makeCase(dir.path() / "d", {.exposure = {1.0, 1.0, 1.0}, .givenLights = true});
  const PipelineResult r = runPipeline(caseOptions(dir.path() / "d"));
  const Scene scene = loadScene(dir.path() / "d/scene.json", {.loadPhotos = false});
  const auto got = fittedAlbedos(dir.path() / "d/twin", 300, 0.3);
  ASSERT_GE(got.size(), 5u);
  std::vector<double> lum;
  for (const auto& [name, a] : got) {
    const Vec3d truth = trueAlbedo(scene.partId(name)).cast<double>();
    std::printf("%-12s albedo %.3f %.3f %.3f  truth %.3f %.3f %.3f\n", name.c_str(), a.first[0],
                a.first[1], a.first[2], truth[0], truth[1], truth[2]);
    lum.push_back(luminance(a.first) / luminance(truth));
    for (int c : {0, 2})
      EXPECT_NEAR((a.first[c] / a.first[1]) / (truth[c] / truth[1]), 1.0, 0.05)
          << name << " channel " << c << " against green";
  }
  std::sort(lum.begin(), lum.end());
  // the level: the median part within 8 %, every part within 15 % (measured 1.045 for the
  // median, with and without the stage; 1.028 with the lamps sampled in round 1's grids: a matte
  // part's roughness, which its photo does not show, and the coarse furniture move it;
  // FixedPartsAnchor above)
  EXPECT_NEAR(lum[lum.size() / 2], 1.0, 0.08);
  for (double l : lum) EXPECT_NEAR(l, 1.0, 0.15);
  (void)r;
}

// Issue 19, item 4: a part's aligned mask M_aln in two views agree through the geometry. The
// label images come from the sample's exact geometry (as makeCase writes them) and M_aln is made
// per view on the coarse one (each furniture object moved 2-5 cm, turned 1-3 degrees, scaled
// 2-4 %), as the align stage makes it; of the points of a part's M_aln in one view that another
// view sees on the part's interior, at least 90 % land in that view's M_aln.
TEST(MultiViewMasks, a_parts_aligned_masks_agree_across_views_on_the_coarse_geometry) {
  const Twin exact = loadTwin(kSample / "gt/twin");
  const Scene coarse = loadScene(kSample / "scene.json", {.loadPhotos = false});
  const auto gray = [](const Scene& s) {
    std::vector<PartMaterial> m;
    for (const Part& p : s.parts) m.push_back(PartMaterial::defaultGray(p.name));
    return m;
  };
  const PathTracer exactTracer(exact.scene, gray(exact.scene));
  const PathTracer coarseTracer(coarse, gray(coarse));
  std::vector<Camera> cams;
  std::vector<GBuffer> gbuffers;
  std::vector<align::ViewAlignment> aligned;
  for (const io::CameraDesc& d : cameras()) {
    cams.push_back(Camera::fromDesc(d));
    // labels of the exact geometry, each region pinned to its part of the coarse scene
    const Labels labels = labelsOf(renderGBuffer(exactTracer, cams.back()), exact.scene);
    std::map<int, int> pinned;
    for (const auto& [label, part] : labels.parts) pinned[label] = coarse.partId(part);
    gbuffers.push_back(renderGBuffer(coarseTracer, cams.back()));
    const cv::Mat photo =
        cv::Mat::zeros(labels.image.size(), CV_32FC3);  // read only without labels
    aligned.push_back(align::alignView(photo, labels.image, pinned, gbuffers.back().partId,
                                       gbuffers.back().coverage));
  }
  int pairs = 0;
  for (size_t a = 0; a < cams.size(); ++a)
    for (size_t b = 0; b < cams.size(); ++b) {
      if (a == b) continue;
      const align::Projector projectB = [&](const Vec3d& x, Vec2d* q) {
        return cams[b].project(x, q);
      };
      for (const auto& [part, maskA] : aligned[a].fitMask) {
        const auto maskB = aligned[b].fitMask.find(part);
        if (maskB == aligned[b].fitMask.end()) continue;
        const align::MaskConsistency c =
            align::maskConsistency(part, maskA, gbuffers[a].position, maskB->second,
                                   gbuffers[b].position, gbuffers[b].partId, projectB);
        if (c.seen < 50) continue;
        std::printf("%-12s view %zu -> %zu: %4d of %4d seen, %.3f in M_aln there\n",
                    coarse.parts[part].name.c_str(), a, b, c.seen, c.pixels, c.share());
        // measured 0.94-1.00 (the rug the lowest)
        EXPECT_GE(c.share(), 0.9) << coarse.parts[part].name << " view " << a << " -> " << b;
        ++pairs;
      }
    }
  EXPECT_GE(pairs, 12) << "parts seen in two views";
}

// ---------------------------------------------------------------- the multi-view example

// scripts/make_multiview_example.py on the shared blender-room case: view0 and novel0 as input
// views, novel1 held back. Blender rendered every view at one exposure, so the solved exposure of
// novel0 is 1; the held-back view is scored; parts both views see record both.
TEST(BlenderRoomMultiView, runs_end_to_end_with_two_views_of_one_exposure) {
  const fs::path room = fs::path(PS_SHARED_DATA_DIR) / "examples/blender-room";
  if (!fs::exists(room / "scene.json") || !fs::exists(room / "gt/novel0_segments.png"))
    GTEST_SKIP() << "shared data not present: " << room;
  io::TempDir dir("ps-multiview-example");
  const std::string cmd =
      "python3 " + (fs::path(PS_SOURCE_DIR) / "scripts/make_multiview_example.py").string() + " " +
      room.string() + " " + (dir.path() / "example").string() + " > /dev/null";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  PipelineOptions o;
  o.scene = dir.path() / "example/two-views/scene.json";
  o.out = dir.path() / "twin";
  o.preset = "fast";
  o.textureSize = 32;
  o.workWidth = 160;
  o.maxFitIterations = 5;
  o.writeGltf = false;
  o.renderSpp = 8;
  o.evalSpp = 8;
  o.bankCache = test::kBankCache;
  const PipelineResult r = runPipeline(o);
  ASSERT_EQ(r.exposure.size(), 2u);
  EXPECT_DOUBLE_EQ(r.exposure[0], 1.0);
  // 6 %: within 5 % while homogeneous roughness came from statLoss, 5.1 % since it comes from
  // a predicted highlight and the prior (the fitted materials are what lights1 solves under)
  EXPECT_NEAR(r.exposure[1], 1.0, 0.06);
  const nlohmann::json metrics = io::readJsonFile(o.out / "metrics.json");
  ASSERT_TRUE(metrics.contains("novel")) << metrics.dump().substr(0, 400);
  bool novel1 = false;
  for (const auto& n : metrics["novel"]) novel1 |= n.dump().find("novel1") != std::string::npos;
  EXPECT_TRUE(novel1) << "the held-back view is not scored";
  // the coarse CAD's furniture moved onto both views' labels (poses.json, `check`, the report);
  // the twin's OBJ is the moved one
  const report::ViewsSummary views = report::summarizeViews(o.out);
  ASSERT_EQ(views.objects.size(), 5u);
  for (const auto& b : views.objects) {
    EXPECT_TRUE(b.moved) << b.name;
    EXPECT_LT(b.after, b.before) << b.name;
  }
  EXPECT_NE(report::viewsText(views).find("object chair_2"), std::string::npos);
  EXPECT_NE(io::readTextFile(o.out / "geometry/room.obj"), io::readTextFile(room / "room.obj"));
  int both = 0, fittedInNovel0 = 0;
  for (const auto& e : fs::directory_iterator(o.out / "materials")) {
    const nlohmann::json m = io::readJsonFile(e.path());
    if (!m["fit"].contains("views")) continue;
    both += m["fit"]["views"].size() == 2;
    fittedInNovel0 += m["fit"]["view"] == 1;
  }
  EXPECT_GE(both, 5) << "parts seen in both views";
  EXPECT_GE(fittedInNovel0, 1) << "no part was fitted in the second view";
  // the colour of the large parts' albedos (log RGB against the truth's, its mean over the
  // channels removed): the window's measured light sets it, where the guesses' colour cast put
  // the lamps' warmth into the walls and floor before (lighting/solve.hpp)
  const nlohmann::json truth = io::readJsonFile(room / "gt/parts.json")["parts"];
  double colour = 0;
  int large = 0;
  for (const auto& [name, t] : truth.items()) {
    const fs::path file = o.out / "materials" / (name + ".json");
    if (t.value("pixels_view0", 0) < 20000 || !fs::exists(file)) continue;
    const nlohmann::json m = io::readJsonFile(file);
    if (!m.contains("homogeneous") || !t.contains("albedo_mean_view0_linear")) continue;
    Vec3d e;
    for (int c = 0; c < 3; ++c)
      e[c] = std::log(std::max(1e-4, m["homogeneous"]["albedo"][c].get<double>()) /
                      t["albedo_mean_view0_linear"][c].get<double>());
    const double error = (e.array() - e.mean()).abs().mean();
    colour += error;
    ++large;
    std::printf("  %-18s albedo colour error %.3f\n", name.c_str(), error);
  }
  ASSERT_GE(large, 3) << "large parts with a homogeneous albedo";
  EXPECT_LT(colour / large, 0.1);
  // `photoscene check OUT` and the report list the views, their exposures and each part's view
  const report::ViewsSummary s = report::summarizeViews(o.out);
  ASSERT_EQ(s.views.size(), 2u);
  EXPECT_DOUBLE_EQ(s.views[1].exposure, r.exposure[1]);
  EXPECT_EQ(s.views[0].parts + s.views[1].parts,
            static_cast<int>(
                std::count_if(s.parts.begin(), s.parts.end(),
                              [](const report::ViewsSummary::Part& p) { return p.view >= 0; })));
  EXPECT_NE(report::viewsText(s).find("view 1*"), std::string::npos) << report::viewsText(s);
  std::ifstream html(o.out / "report.html");
  const std::string page((std::istreambuf_iterator<char>(html)), std::istreambuf_iterator<char>());
  EXPECT_NE(page.find("id=\"view-choice\""), std::string::npos);
}

}  // namespace
}  // namespace ps
