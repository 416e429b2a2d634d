// The stage model (src/stage.hpp, src/runner.hpp): every cache key is derived from what the
// stage declares, so perturbing one declared input (a scene.json value, a file's bytes, an
// option) changes the keys of exactly the stages downstream of it; a stage that reads what it did
// not declare is refused; and the stale-cache cases of issue 21 (an edited environment light, an
// edited fixed material) are recomputed on the rerun.
#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <fstream>
#include <functional>
#include <memory>

#include "../src/runner.hpp"
#include "../src/stages.hpp"
#include "photoscene/core.hpp"
#include "photoscene/graph.hpp"
#include "photoscene/io.hpp"
#include "photoscene/optim.hpp"
#include "sample_paths.hpp"
#include "shared_run.hpp"

namespace ps::pipeline {
namespace {

namespace fs = std::filesystem;
using Pointer = nlohmann::json::json_pointer;

using test::kSample;
using test::sampleOptions;
using test::sampleSceneJson;

/// The bundled sample copied into a temporary folder, so that its files can be edited.
struct SampleCopy {
  io::TempDir dir{"ps-stages"};
  SampleCopy() { fs::copy(kSample, dir.path(), fs::copy_options::recursive); }
  fs::path scene() const { return dir / "scene.json"; }
};

// ---------------------------------------------------------------- declared keys

TEST(Stages_DeclaredKeys, expand_to_the_units_own_view_and_part) {
  const nlohmann::json j = {{"views", {{{"camera", 1}}, {{"camera", 2}}}},
                            {"parts", {{"floor", {{"graph", "wood"}}}}},
                            {"lights", {{"area", {{{"part", "lamp"}}, {{"center", {0, 1, 0}}}}}}}};
  auto strings = [](const std::vector<Pointer>& ps) {
    std::vector<std::string> s;
    for (const Pointer& p : ps) s.push_back(p.to_string());
    return s;
  };
  using V = std::vector<std::string>;
  EXPECT_EQ(strings(expandKey(j, "views[].camera", Unit::View, 1, "")), V{"/views/1/camera"});
  EXPECT_EQ(strings(expandKey(j, "views[].camera", Unit::Global, 0, "")),
            (V{"/views/0/camera", "/views/1/camera"}));
  EXPECT_EQ(strings(expandKey(j, "views[].camera", Unit::Part, 0, "floor")),
            (V{"/views/0/camera", "/views/1/camera"}));
  // a part's own entry, present or not (adding it must change the key)
  EXPECT_EQ(strings(expandKey(j, "parts.{}.graph", Unit::Part, 0, "floor")),
            V{"/parts/floor/graph"});
  EXPECT_EQ(strings(expandKey(j, "parts.{}.fixed", Unit::Part, 1, "rug")), V{"/parts/rug/fixed"});
  EXPECT_EQ(strings(expandKey(j, "parts.{}.graph", Unit::Global, 0, "")), V{"/parts/floor/graph"});
  EXPECT_EQ(strings(expandKey(j, "lights.area[].part", Unit::Global, 0, "")),
            (V{"/lights/area/0/part", "/lights/area/1/part"}));
  EXPECT_EQ(strings(expandKey(j, "lights.environment", Unit::Global, 0, "")),
            V{"/lights/environment"});
  EXPECT_EQ(strings(expandKey(j, "", Unit::Global, 0, "")), V{""});
  EXPECT_TRUE(keyCovers("lights", "lights.environment.image"));
  EXPECT_TRUE(keyCovers("", "views[].camera"));
  EXPECT_TRUE(keyCovers("views[].camera", "views[].camera"));
  EXPECT_FALSE(keyCovers("lights.area", "lights"));
  EXPECT_FALSE(keyCovers("lights.area", "lights.auto_ceiling_spacing"));
  EXPECT_TRUE(isFileKey(Pointer("/views/3/image")));
  EXPECT_TRUE(isFileKey(Pointer("/lights/environment/image")));
  EXPECT_FALSE(isFileKey(Pointer("/views/3/camera")));
}

/// Which units each perturbation must change: the units that declare the input, then every unit
/// downstream (computed from the declarations, apart from the runner's hashing).
using Changed = std::map<std::string, std::vector<bool>>;

Changed expectedChange(const Runner& runner, const Context& ctx,
                       const std::function<bool(const StageDecl&, int unit)>& declares) {
  Changed c;
  for (const auto& s : runner.stages()) {
    const StageDecl& d = s->decl;
    std::vector<bool> v(Runner::unitCount(ctx, d.unit));
    for (size_t u = 0; u < v.size(); ++u) {
      bool changed = declares(d, static_cast<int>(u));
      for (const std::string& up : d.after) {
        Unit upUnit = Unit::Global;
        for (const auto& t : runner.stages())
          if (t->decl.name == up) upUnit = t->decl.unit;
        const std::vector<bool>& uc = c.at(up);
        if (upUnit == d.unit && d.unit != Unit::Global)
          changed = changed || uc[u];
        else
          for (bool b : uc) changed = changed || b;
      }
      v[u] = changed;
    }
    c[d.name] = v;
  }
  return c;
}

/// Every leaf of a JSON value with its pointer.
void leaves(const nlohmann::json& j, const Pointer& at, std::vector<Pointer>& out) {
  if (j.is_object() && !j.empty()) {
    for (auto it = j.begin(); it != j.end(); ++it) leaves(it.value(), at / it.key(), out);
  } else if (j.is_array() && !j.empty()) {
    for (size_t k = 0; k < j.size(); ++k) leaves(j[k], at / k, out);
  } else {
    out.push_back(at);
  }
}

nlohmann::json perturbed(const nlohmann::json& v) {
  if (v.is_boolean()) return !v.get<bool>();
  if (v.is_number()) return v.get<double>() + 0.5;
  if (v.is_string()) return v.get<std::string>() + "-edited";
  return 1;
}

// The bundled sample with a second view (so that a per-view stage is seen to cover its own view
// only), its keys, and a check of the keys after one perturbation against the declarations.
class Stages_Keys : public ::testing::Test {
 protected:
  void SetUp() override {
    nlohmann::json j = io::readJsonFile(s_.scene());
    j["views"][1] = j["views"][0];
    j["views"][1]["image"] = "photos/view1.png";
    j["views"][1]["segments"] = "segments/view1.png";
    fs::copy_file(s_.dir / "photos/view0.png", s_.dir / "photos/view1.png");
    fs::copy_file(s_.dir / "segments/view0.png", s_.dir / "segments/view1.png");
    io::writeJsonFile(s_.scene(), j);
    options_ = sampleOptions(s_.scene(), s_.dir / "out");
    ctx_ = Context::load(options_);
    runner_ = std::make_unique<Runner>(pipelineStages(options_));
    original_ = inputs().scene.desc.rawJson;
    fs::create_directories(options_.out);
    io::writeJsonFile(options_.out / "metrics.json", nlohmann::json{{"a", 1}});
    result_ = runner_->keys(*ctx_);
  }
  RunInputs& inputs() { return ContextTesting::inputs(*ctx_); }

  /// Compares the keys now with the base keys: a unit's key must change exactly where `expected`
  /// says; returns how many units changed.
  int check(const std::string& what, const Changed& expected) {
    const StageKeys now = runner_->keys(*ctx_);
    int changed = 0;
    for (const auto& [stage, units] : expected)
      for (size_t u = 0; u < units.size(); ++u) {
        const bool differs = now.at(stage)[u] != result_.at(stage)[u];
        changed += differs;
        EXPECT_EQ(differs, units[u])
            << what << ": stage " << stage << " unit " << u
            << (units[u] ? " should change and does not" : " changes without reading it");
      }
    return changed;
  }
  Changed expected(const std::function<bool(const StageDecl&, int unit)>& declares) {
    return expectedChange(*runner_, *ctx_, declares);
  }
  /// The units whose declared scene.json keys hold another value in `edited` (present or not),
  /// or hold the file at `file`.
  std::function<bool(const StageDecl&, int)> sceneDeclares(const nlohmann::json& edited,
                                                           const Pointer& file) {
    auto valueAt = [](const nlohmann::json& j, const Pointer& p) {
      return j.contains(p) ? j.at(p) : nlohmann::json("<absent>");
    };
    return [this, edited, file, valueAt](const StageDecl& d, int u) {
      const std::string part = d.unit == Unit::Part ? ctx_->parts[u].name : "";
      for (const std::string& key : d.scene)
        for (const nlohmann::json* j :
             std::initializer_list<const nlohmann::json*>{&original_, &edited})
          for (const Pointer& p : expandKey(*j, key, d.unit, u, part)) {
            if (valueAt(original_, p) != valueAt(edited, p)) return true;
            if (!file.empty() && (p == file || file.to_string().rfind(p.to_string() + "/", 0) == 0))
              return true;
          }
      return false;
    };
  }
  int checkScene(const std::string& what, const nlohmann::json& edited) {
    inputs().scene.desc.rawJson = edited;
    const int n = check(what, expected(sceneDeclares(edited, Pointer())));
    inputs().scene.desc.rawJson = original_;
    return n;
  }
  static std::function<bool(const StageDecl&, int)> declaresOption(const std::string& name) {
    return [name](const StageDecl& d, int) {
      return std::find(d.options.begin(), d.options.end(), name) != d.options.end();
    };
  }

  SampleCopy s_;
  PipelineOptions options_;
  std::unique_ptr<Context> ctx_;
  std::unique_ptr<Runner> runner_;
  nlohmann::json original_;
  StageKeys result_;
};

TEST_F(Stages_Keys, every_scene_json_value_changes_exactly_the_keys_downstream_of_it) {
  std::vector<Pointer> values;
  leaves(original_, Pointer(), values);
  ASSERT_GT(values.size(), 60u);
  for (const Pointer& at : values) {
    nlohmann::json edited = original_;
    edited[at] = perturbed(original_[at]);
    EXPECT_GT(checkScene("scene.json " + at.to_string(), edited), 0)
        << at.to_string() << " is read by no stage";
  }
  EXPECT_EQ(runner_->keys(*ctx_), result_);  // restored: the same keys again
}

TEST_F(Stages_Keys, adding_a_key_changes_exactly_the_keys_downstream_of_it) {
  // keys the sample does not have: an environment light, a fixed material, a forced graph, a
  // given category, a skip
  const std::vector<std::pair<std::string, nlohmann::json>> added = {
      {"/lights/environment", {{"radiance", {1, 1, 1}}, {"rotation_deg", 30}}},
      {"/lights/environment/window_parts", {"wall_front"}},
      {"/parts/cabinet/fixed", {{"albedo", {0.3, 0.3, 0.3}}}},
      {"/parts/floor/graph", "wood_planks"},
      {"/parts/floor/category", "wood"},
      {"/parts/rug/skip", true},
      {"/options/refine_poses", false}};
  for (const auto& [where, value] : added) {
    nlohmann::json edited = original_;
    edited[Pointer(where)] = value;
    EXPECT_GT(checkScene("scene.json + " + where, edited), 0);
  }
}

TEST_F(Stages_Keys, a_files_bytes_change_exactly_the_keys_downstream_of_it) {
  for (const char* where : {"/geometry", "/views/0/image", "/views/0/segments", "/views/1/image"}) {
    const Pointer at(where);
    const fs::path file = s_.dir / original_[at].get<std::string>();
    const std::string bytes = [&] {
      std::ifstream f(file, std::ios::binary);
      return std::string(std::istreambuf_iterator<char>(f), {});
    }();
    std::ofstream(file, std::ios::binary | std::ios::app) << '\n';
    EXPECT_GT(check(std::string("bytes of ") + where, expected(sceneDeclares(original_, at))), 0);
    std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
  }
  EXPECT_EQ(runner_->keys(*ctx_), result_);
}

TEST_F(Stages_Keys, each_option_changes_exactly_the_keys_downstream_of_it) {
  const fs::path gtImage = s_.dir / "gt/novel0.exr";
  const std::map<std::string, std::function<void(RunInputs&, bool)>> edits = {
      {"preset", [](RunInputs& i, bool on) { i.preset = on ? "paper" : "fast"; }},
      {"texture_size", [](RunInputs& i, bool on) { i.options.textureSize = on ? 64 : 128; }},
      {"work_width", [](RunInputs& i, bool on) { i.options.workWidth = on ? 200 : 320; }},
      {"mean_albedo", [](RunInputs& i, bool on) { i.options.meanAlbedo = on ? 0.4 : 0.5; }},
      {"render_spp",
       [](RunInputs& i, bool on) {
         i.options.renderSpp = on ? std::optional<int>(8) : std::nullopt;
       }},
      {"eval_spp",
       [](RunInputs& i, bool on) {
         i.options.evalSpp = on ? std::optional<int>(4) : std::nullopt;
       }},
      {"max_fit_iterations",
       [](RunInputs& i, bool on) {
         i.options.maxFitIterations = on ? std::optional<int>(3) : std::nullopt;
       }},
      {"selection",
       [](RunInputs& i, bool on) {
         i.options.selection = on ? std::optional<SynthesisOptions>(SynthesisOptions{}) : std::nullopt;
       }},
      {"baseline",
       [](RunInputs& i, bool on) {
         i.options.baseline = on ? Baseline::PixelMedian : Baseline::None;
       }},
      {"write_gltf", [](RunInputs& i, bool on) { i.options.writeGltf = !on; }},
      {"fit_views", [](RunInputs& i, bool on) { i.options.fitAllViews = on; }},
      {"denoise", [](RunInputs& i, bool on) { i.options.denoise = !on; }},
      {"incident",
       [](RunInputs& i, bool on) {
         i.options.incidentSamples = on ? std::optional<int>(32) : std::nullopt;
         i.options.incidentDirectSamples = on ? std::optional<int>(16) : std::nullopt;
       }},
      {"library",
       [](RunInputs& i, bool on) {
         i.bankName = on ? i.bankName + "-edited" : i.bankName.substr(0, i.bankName.size() - 7);
       }},
      {"ground_truth", [&](RunInputs&, bool on) {
         if (on)
           std::ofstream(gtImage, std::ios::binary | std::ios::app) << '\n';
         else
           fs::copy_file(kSample / "gt/novel0.exr", gtImage, fs::copy_options::overwrite_existing);
       }}};
  for (const std::string& name : optionNames()) {
    ASSERT_TRUE(edits.count(name)) << "the test does not perturb option " << name;
    edits.at(name)(inputs(), true);
    EXPECT_GT(check("option " + name, expected(declaresOption(name))), 0)
        << name << " is read by no stage";
    edits.at(name)(inputs(), false);
  }
  EXPECT_EQ(runner_->keys(*ctx_), result_);
}

TEST_F(Stages_Keys, each_selection_setting_changes_the_keys_of_the_stages_that_read_it) {
  // the "selection" option is one struct: a field the key leaves out reuses a stale selection
  // (textureRequired was left out once). Each edit against SynthesisOptions{} itself.
  const std::vector<std::pair<const char*, std::function<void(SynthesisOptions&)>>> edits = {
      {"shortlist", [](SynthesisOptions& s) { s.shortlist += 1; }},
      {"categories", [](SynthesisOptions& s) { s.categories += 1; }},
      {"steps", [](SynthesisOptions& s) { s.steps += 1; }},
      {"voteK", [](SynthesisOptions& s) { s.voteK += 1; }},
      {"homogeneous", [](SynthesisOptions& s) { s.homogeneous = !s.homogeneous; }},
      {"textureMargin", [](SynthesisOptions& s) { s.textureMargin += 0.01; }},
      {"maxPixelErrorRatio", [](SynthesisOptions& s) { s.maxPixelErrorRatio += 0.1; }},
      {"maxContrastRatio", [](SynthesisOptions& s) { s.maxContrastRatio += 0.1; }},
      {"coarseContrastScale", [](SynthesisOptions& s) { s.coarseContrastScale += 1; }},
      {"maxChromaRatio", [](SynthesisOptions& s) { s.maxChromaRatio += 0.1; }},
      {"maxChromaOutside", [](SynthesisOptions& s) { s.maxChromaOutside += 0.01; }},
      {"startFromNearestDraw",
       [](SynthesisOptions& s) { s.startFromNearestDraw = !s.startFromNearestDraw; }},
      {"warmStartFit", [](SynthesisOptions& s) { s.warmStartFit = !s.warmStartFit; }},
      {"heldOut", [](SynthesisOptions& s) { s.heldOut = !s.heldOut; }},
      {"minHeldOutPixels", [](SynthesisOptions& s) { s.minHeldOutPixels += 1; }},
      {"bandShape", [](SynthesisOptions& s) { s.bandShape = 2.0f; }},
      {"textureRequired", [](SynthesisOptions& s) { s.textureRequired = !s.textureRequired; }},
      {"heldParameters", [](SynthesisOptions& s) { s.heldParameters.clear(); }}};
  inputs().options.selection = SynthesisOptions{};
  const StageKeys base = runner_->keys(*ctx_);
  for (const auto& [name, edit] : edits) {
    SynthesisOptions s;
    edit(s);
    inputs().options.selection = s;
    const StageKeys now = runner_->keys(*ctx_);
    for (const char* stage : {"select", "fit"}) EXPECT_NE(now.at(stage), base.at(stage)) << name;
  }
  inputs().options.selection.reset();
  EXPECT_EQ(runner_->keys(*ctx_), result_);
}

TEST_F(Stages_Keys, an_output_file_changes_the_keys_of_the_stages_that_read_it) {
  // report reads metrics.json, which `photoscene eval` may have written again
  io::writeJsonFile(options_.out / "metrics.json", nlohmann::json{{"a", 2}});
  EXPECT_EQ(check("OUT/metrics.json",
                  expected([](const StageDecl& d, int) { return !d.outputs.empty(); })),
            1);
}

TEST_F(Stages_Keys, what_changes_no_result_changes_no_key) {
  inputs().options.threads = 7;
  inputs().options.bankCache = "/elsewhere";
  inputs().options.useStageCache = false;
  inputs().options.writeReport = false;  // whether report runs, not what it reads
  inputs().options.out = s_.dir / "elsewhere";
  fs::create_directories(inputs().options.out);
  io::writeJsonFile(inputs().options.out / "metrics.json", nlohmann::json{{"a", 1}});
  EXPECT_EQ(runner_->keys(*ctx_), result_);
}

// ---------------------------------------------------------------- reads as declared

TEST(Stages_Reads, a_stage_reading_what_it_did_not_declare_is_refused) {
  std::unique_ptr<Context> ctx =
      Context::load(sampleOptions(kSample / "scene.json", "/nonexistent-out"));
  StageDecl d;
  d.name = "probe";
  d.unit = Unit::View;
  d.scene = {"views[].camera", "geometry"};
  d.options = {"work_width"};
  const Reads view(*ctx, d, 0);
  EXPECT_NO_THROW(view.camera(0));
  EXPECT_THROW(view.camera(1), Exception);        // another view's
  EXPECT_THROW(view.photo(0), Exception);         // views[].image
  EXPECT_THROW(view.litScene(), Exception);       // lights
  EXPECT_THROW(view.sceneGeometry(), Exception);  // lights.area
  EXPECT_THROW(view.budget(), Exception);         // preset
  EXPECT_THROW(view.seed(), Exception);           // options.seed
  EXPECT_THROW(view.library(), Exception);
  EXPECT_THROW(view.outFile("metrics.json"), Exception);
  d.unit = Unit::Part;
  d.scene = {"parts.{}.fixed", "parts.{}.graph"};
  const Reads part(*ctx, d, 2);
  EXPECT_NO_THROW(part.partFixed(2));
  EXPECT_NO_THROW(part.partGraph(2));
  EXPECT_THROW(part.partFixed(3), Exception);  // another part's
  EXPECT_THROW(part.partSkip(2), Exception);   // parts.{}.skip
  try {
    part.partSkip(2);
  } catch (const Exception& e) {
    EXPECT_NE(std::string(e.what()).find("stage probe reads scene.json key 'parts.{}.skip'"),
              std::string::npos)
        << e.what();
  }
}

TEST(Stages_Runner, orders_by_declared_dependencies_and_refuses_unknown_ones) {
  const StageList list = pipelineStages(PipelineOptions());
  // the method's list, reversed, comes back in an order where every stage follows its upstream
  StageList stages = pipelineStages(PipelineOptions());
  std::reverse(stages.begin(), stages.end());
  const Runner runner(std::move(stages));
  std::vector<std::string> seen;
  for (const auto& s : runner.stages()) {
    for (const std::string& up : s->decl.after)
      EXPECT_NE(std::find(seen.begin(), seen.end(), up), seen.end())
          << s->decl.name << " before " << up;
    seen.push_back(s->decl.name);
  }
  EXPECT_EQ(seen.size(), list.size());
  StageList bad = pipelineStages(PipelineOptions());
  bad.back()->decl.after.push_back("no-such-stage");
  EXPECT_THROW(Runner{std::move(bad)}, Exception);
  StageList unknown = pipelineStages(PipelineOptions());
  unknown.front()->decl.options.push_back("no_such_option");
  EXPECT_THROW(Runner{std::move(unknown)}, Exception);
}

// The README's example ("Adding a stage"), compiled and run: per view, the pixels the light solve
// uses, as OUT/masks/view<i>_light.png.
class LightMaskStage : public Stage {
 public:
  LightMaskStage() : Stage("light_mask", Unit::View) {
    decl.after = {"align"};  // reads ViewWork::lightMask
    decl.writes = {"OUT/masks/view<i>_light.png"};
  }
  bool compute(Context& ctx, const Reads& in, int v) override {
    io::writeRawImage(file(in, v), ctx.views[v].lightMask);
    return true;
  }
  void save(const Context&, int, Archive&) const override {}  // the file is the result
  bool load(Context&, const Reads& in, int v, Archive&) override { return fs::exists(file(in, v)); }

 private:
  static fs::path file(const Reads& in, int v) {
    fs::create_directories(in.out() / "masks");
    return in.out() / "masks" / ("view" + std::to_string(v) + "_light.png");
  }
};

TEST(Stages_Runner, a_new_stage_is_keyed_cached_and_reported_from_its_declaration_alone) {
  io::TempDir dir;
  auto run = [&] {
    std::unique_ptr<Context> ctx =
        Context::load(sampleOptions(kSample / "scene.json", dir / "out"));
    ctx->cache = std::make_unique<StageCache>(dir / "out/.cache");
    StageList stages;
    stages.push_back(makePartsStage());
    stages.push_back(std::make_unique<LightMaskStage>());  // before its upstream: the runner orders
    stages.push_back(makePosesStage());
    stages.push_back(makeGeometryStage());
    stages.push_back(makeAlignStage());
    Runner(std::move(stages)).run(*ctx);
    const StageRecord* r = ctx->result.stage("light_mask");
    return r ? std::make_pair(r->computed, r->cached) : std::make_pair(-1, -1);
  };
  EXPECT_EQ(run(), std::make_pair(1, 0));
  const cv::Mat mask = io::readDataImage(dir / "out/masks/view0_light.png");
  EXPECT_GT(cv::countNonZero(mask.reshape(1)), 1000);  // the walls, floor and furniture agree
  EXPECT_EQ(run(), std::make_pair(0, 1));              // unchanged: loaded
  fs::remove(dir / "out/masks/view0_light.png");
  EXPECT_EQ(run(), std::make_pair(1, 0));  // its file gone: written again
}

// ---------------------------------------------------------------- stale cache (issue 21)

/// A quick run of `scene` into `out`: 96 px wide, 2 fit steps, 16-texel maps, 2 spp, no glTF or
/// report.
PipelineOptions quickRun(const fs::path& scene, const fs::path& out) {
  PipelineOptions o = sampleOptions(scene, out);
  o.workWidth = 96;
  o.maxFitIterations = 2;
  o.textureSize = 16;
  o.renderSpp = 2;
  o.evalSpp = 2;
  o.writeGltf = o.writeReport = false;
  return o;
}

// A small, quick version of the sample (working width 96, two fit iterations) with a fixed
// material and an environment light seen through a window, run once; each test edits one of them
// and reruns into the same output folder.
class StaleCache : public test::SharedRun<StaleCache> {
 protected:
  static nlohmann::json baseScene() {
    nlohmann::json j = sampleSceneJson();
    j["parts"]["cabinet"]["fixed"] = {{"albedo", {0.6, 0.5, 0.4}}, {"roughness", 0.5}};
    j["lights"]["environment"] = {{"image", (dir_->path() / "sky.exr").string()},
                                  {"window_parts", {"wall_front"}},
                                  {"rotation_deg", 0}};
    return j;
  }
  static PipelineResult run(const nlohmann::json& scene) {
    io::writeJsonFile(dir_->path() / "scene.json", scene);
    return runPipeline(quickRun(dir_->path() / "scene.json", dir_->path() / "twin"));
  }
  static void SetUpTestSuite() {
    dir_ = std::make_unique<io::TempDir>("ps-stale");
    // a sky brighter towards one side, so that rotating it changes the light through the window
    cv::Mat sky(16, 32, CV_32FC3);
    for (int y = 0; y < sky.rows; ++y)
      for (int x = 0; x < sky.cols; ++x)
        sky.at<cv::Vec3f>(y, x) = cv::Vec3f(1, 1, 1) * (0.2f + 2.0f * x / sky.cols);
    io::writeImage(dir_->path() / "sky.exr", sky);
    result_ = std::make_unique<PipelineResult>(run(baseScene()));
  }
};

TEST_F(StaleCache, an_edited_environment_light_recomputes_the_lights_and_the_grids) {
  nlohmann::json j = baseScene();
  j["lights"]["environment"]["rotation_deg"] = 90;
  const PipelineResult r = run(j);
  EXPECT_EQ(r.stage("geometry")->computed, 0);
  EXPECT_EQ(r.stage("align")->computed, 0);
  EXPECT_EQ(r.stage("lights0")->computed, 1);
  EXPECT_EQ(r.stage("incident0")->computed, 1);
  EXPECT_EQ(r.stage("lights1")->computed, 1);
  EXPECT_EQ(r.stage("incident1")->computed, 1);
}

TEST_F(StaleCache, an_edited_fixed_material_recomputes_the_lights_and_the_grids) {
  nlohmann::json j = baseScene();
  j["parts"]["cabinet"]["fixed"]["albedo"] = {0.1, 0.1, 0.1};
  const PipelineResult r = run(j);
  EXPECT_EQ(r.stage("geometry")->computed, 0);
  EXPECT_EQ(r.stage("align")->computed, 0);
  EXPECT_EQ(r.stage("lights0")->computed, 1);
  EXPECT_EQ(r.stage("incident0")->computed, 1);
  // selection by synthesis fits its finalists under incident0: new grids, a new selection
  EXPECT_EQ(r.stage("select")->computed, result_->stage("select")->computed);
  EXPECT_GT(r.stage("select")->computed, 0);
  // a darker fixed part explains less of the photo: the lights come out otherwise
  ASSERT_EQ(r.lightRadiance.size(), result_->lightRadiance.size());
  double diff = 0;
  for (size_t k = 0; k < r.lightRadiance.size(); ++k)
    diff += (r.lightRadiance[k] - result_->lightRadiance[k]).norm();
  EXPECT_GT(diff, 0.0);
}

// Maps exported below the fit's map size are the fitted map area-downsampled, not the graph
// drawn at the small size: a pattern finer than a texel aliases there (fabric_windowpane's grid
// at 64 texels kept its vertical lines only, and the twin rendered stripes the fit never saw).
TEST(Stages_Export, maps_below_the_fits_size_are_the_fitted_map_downsampled) {
  io::TempDir dir("ps-export-size");
  nlohmann::json j = sampleSceneJson();
  j["parts"]["wall_back"]["graph"] = "fabric_windowpane";
  io::writeJsonFile(dir.path() / "scene.json", j);
  const PipelineOptions o = quickRun(dir.path() / "scene.json", dir.path() / "twin");
  ASSERT_EQ(o.textureSize, 16);
  const PipelineResult r = runPipeline(o);
  const nlohmann::json m = io::readJsonFile(r.out / "materials/wall_back.json");
  ASSERT_EQ(m["graph"], "fabric_windowpane");
  MaterialGraph g = GraphLibrary::load().create("fabric_windowpane");
  for (const auto& [name, v] : m["params"].items())
    g.setParameter(name, v.is_array() ? v.get<std::vector<float>>()
                                      : std::vector<float>{v.get<float>()});
  const int fitSize = PartFitOptions::preset(r.preset).mapSize;
  ASSERT_GT(fitSize, o.textureSize);
  cv::Mat expected;
  cv::resize(g.evaluate(fitSize, MapSet::of({MapKind::Albedo})).albedo, expected,
             cv::Size(o.textureSize, o.textureSize), 0, 0, cv::INTER_AREA);
  const cv::Mat written = io::readImage(r.out / "textures/wall_back_albedo.png");
  const cv::Mat direct = g.evaluate(o.textureSize, MapSet::of({MapKind::Albedo})).albedo;
  auto maxDiff = [](const cv::Mat& a, const cv::Mat& b) {
    double d = 0;
    const cv::Mat diff = cv::abs(a - b);
    cv::minMaxLoc(diff.reshape(1), nullptr, &d);
    return d;
  };
  std::printf("albedo at %d: written against the fitted map downsampled %.4f, drawn at %d %.4f\n",
              o.textureSize, maxDiff(written, expected), o.textureSize, maxDiff(direct, expected));
  ASSERT_EQ(written.size(), expected.size());
  EXPECT_LT(maxDiff(written, expected), 0.01);  // 8-bit sRGB quantisation
  EXPECT_GT(maxDiff(direct, expected), 0.05);   // drawn at 16 it is another map
}

}  // namespace
}  // namespace ps::pipeline
