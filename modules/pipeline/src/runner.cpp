// The stage runner (runner.hpp): keys derived from the declarations, the cache, the stage table.
#include "runner.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <optional>
#include <thread>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "photoscene/core.hpp"
#include "photoscene/core/memory.hpp"
#include "photoscene/eval.hpp"

namespace ps::pipeline {

namespace {

// Bump when the way keys are derived changes, so entries of older runs are not reused.
constexpr uint64_t kKeyFormat = 7;

using Pointer = nlohmann::json::json_pointer;

std::vector<std::string> segments(std::string_view key) {
  std::vector<std::string> out;
  size_t at = 0;
  while (at < key.size()) {
    size_t dot = key.find('.', at);
    if (dot == std::string_view::npos) dot = key.size();
    std::string s(key.substr(at, dot - at));
    if (s.size() > 2 && s.compare(s.size() - 2, 2, "[]") == 0) {
      out.push_back(s.substr(0, s.size() - 2));
      out.push_back("[]");
    } else {
      out.push_back(s);
    }
    at = dot + 1;
  }
  return out;
}

void expand(const nlohmann::json* node, const Pointer& at, const std::vector<std::string>& segs,
            size_t i, Unit unit, int view, const std::string& part, std::vector<Pointer>& out) {
  if (i == segs.size()) {
    out.push_back(at);
    return;
  }
  const std::string& s = segs[i];
  if (s == "[]") {
    if (unit == Unit::View && at.to_string() == "/views") {  // a per-view unit: its own view
      const size_t v = static_cast<size_t>(view);
      const nlohmann::json* child =
          node && node->is_array() && v < node->size() ? &(*node)[v] : nullptr;
      expand(child, at / v, segs, i + 1, unit, view, part, out);
      return;
    }
    if (!node || !node->is_array()) return;
    for (size_t k = 0; k < node->size(); ++k)
      expand(&(*node)[k], at / k, segs, i + 1, unit, view, part, out);
    return;
  }
  if (s == "{}") {
    if (unit == Unit::Part && at.to_string() == "/parts") {  // a per-part unit: its own part
      const nlohmann::json* child =
          node && node->is_object() && node->contains(part) ? &(*node)[part] : nullptr;
      expand(child, at / part, segs, i + 1, unit, view, part, out);
      return;
    }
    if (!node || !node->is_object()) return;
    for (auto it = node->begin(); it != node->end(); ++it)
      expand(&it.value(), at / it.key(), segs, i + 1, unit, view, part, out);
    return;
  }
  const nlohmann::json* child =
      node && node->is_object() && node->contains(s) ? &(*node)[s] : nullptr;
  expand(child, at / s, segs, i + 1, unit, view, part, out);
}

void hashJson(Hasher& h, const nlohmann::json& j, const Pointer& at, const fs::path& baseDir,
              std::map<std::string, uint64_t>& fileHashes) {
  if (j.is_object()) {
    h.add(uint64_t{1}).add(j.size());
    for (auto it = j.begin(); it != j.end(); ++it) {
      h.add(std::string_view(it.key()));
      hashJson(h, it.value(), at / it.key(), baseDir, fileHashes);
    }
  } else if (j.is_array()) {
    h.add(uint64_t{2}).add(j.size());
    for (size_t k = 0; k < j.size(); ++k) hashJson(h, j[k], at / k, baseDir, fileHashes);
  } else if (j.is_string() && isFileKey(at)) {
    // a file: its bytes, not its name
    const fs::path path = baseDir / j.get<std::string>();
    auto [it, fresh] = fileHashes.try_emplace(path.string(), 0);
    if (fresh) it->second = hashFile(path);
    h.add(uint64_t{3}).add(it->second);
  } else {
    h.add(uint64_t{4}).add(std::string_view(j.dump()));
  }
}

void hashOption(Hasher& h, const RunInputs& in, const std::string& name) {
  const PipelineOptions& o = in.options;
  if (name == "preset")
    h.add(std::string_view(in.preset));
  else if (name == "texture_size")
    h.add(o.textureSize);
  else if (name == "work_width")
    h.add(o.workWidth);
  else if (name == "mean_albedo")
    h.add(o.meanAlbedo);
  else if (name == "render_spp")
    h.add(o.renderSpp.value_or(-1));
  else if (name == "max_fit_iterations")
    h.add(o.maxFitIterations.value_or(-1));
  else if (name == "baseline")
    h.add(static_cast<int>(o.baseline));
  else if (name == "write_gltf")
    h.add(o.writeGltf);
  else if (name == "library")
    h.add(std::string_view(in.bankName));
  else if (name == "ground_truth") {
    // what `photoscene eval` compares against: every file findGroundTruth names, by bytes
    const auto gts =
        eval::findGroundTruth(in.scene.desc.baseDir, static_cast<int>(in.views.size()), nullptr);
    h.add(gts.size());
    for (const eval::GroundTruthRender& g : gts) {
      h.add(std::string_view(g.name)).add(hashFile(g.image));
      for (const auto& f : {g.camera, g.lights, g.photoLights})
        h.add(f ? hashFile(*f) : uint64_t{0});
    }
  } else {
    throw Exception("unknown pipeline option '" + name + "' in a stage declaration", __FILE__,
                    __LINE__, __func__);
  }
}

// The testing hooks of pipeline.hpp: a failure or a pause (for a signal) at a stage's start.
void stageTestingHooks(const std::string& stage) {
  if (const char* f = std::getenv("PS_FAIL_AT_STAGE"); f && stage == f)
    throw Exception(
        fmt::format("PS_FAIL_AT_STAGE={}: failure injected into stage {} (a testing hook)", f,
                    stage),
        __FILE__, __LINE__, __func__);
  if (const char* p = std::getenv("PS_PAUSE_AT_STAGE"); p && stage == p) {
    if (const char* marker = std::getenv("PS_PAUSE_MARKER"); marker && *marker)
      std::ofstream(marker) << stage << '\n';
    spdlog::info("PS_PAUSE_AT_STAGE={}: waiting for SIGINT / SIGTERM (a testing hook)", p);
    for (int i = 0; i < 6000 && !interruptRequested(); ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    checkInterrupted();
  }
}

}  // namespace

// ---------------------------------------------------------------- declared keys

std::vector<Pointer> expandKey(const nlohmann::json& scene, std::string_view key, Unit unit,
                               int view, const std::string& part) {
  std::vector<Pointer> out;
  expand(&scene, Pointer(), segments(key), 0, unit, view, part, out);
  return out;
}

bool keyCovers(std::string_view declared, std::string_view key) {
  const std::vector<std::string> d = segments(declared), k = segments(key);
  return d.size() <= k.size() && std::equal(d.begin(), d.end(), k.begin());
}

bool isFileKey(const Pointer& at) {
  const std::string s = at.to_string();
  if (s == "/geometry" || s == "/lights/environment/image") return true;
  if (s.rfind("/views/", 0) != 0) return false;
  const size_t slash = s.find('/', 7);
  if (slash == std::string::npos || slash == 7) return false;
  if (!std::all_of(s.begin() + 7, s.begin() + slash, [](char c) { return c >= '0' && c <= '9'; }))
    return false;
  const std::string rest = s.substr(slash);
  return rest == "/image" || rest == "/segments";
}

// ---------------------------------------------------------------- stage bookkeeping

StageScope::StageScope(Context& ctx, std::string name)
    : ctx_(ctx), exceptions_(std::uncaught_exceptions()) {
  rec_.name = std::move(name);
  checkInterrupted();
  spdlog::info("stage {}", rec_.name);
  stageTestingHooks(rec_.name);
}

StageScope::~StageScope() {
  rec_.seconds = timer_.seconds();
  rec_.peakMemoryMiB = peakMemoryMiB();
  if (std::uncaught_exceptions() > exceptions_)
    spdlog::info("stage {} stopped: {} computed, {} cached (kept in the stage cache)", rec_.name,
                 rec_.computed, rec_.cached);
  else
    spdlog::info("stage {} done: {} computed, {} cached, {:.2f} s, peak memory {:.0f} MiB",
                 rec_.name, rec_.computed, rec_.cached, rec_.seconds, rec_.peakMemoryMiB);
  // stages sharing a row (refine0, refine1) add up
  for (StageRecord& r : ctx_.result.stages)
    if (r.name == rec_.name) {
      r.seconds += rec_.seconds;
      r.computed += rec_.computed;
      r.cached += rec_.cached;
      r.peakMemoryMiB = std::max(r.peakMemoryMiB, rec_.peakMemoryMiB);
      return;
    }
  ctx_.result.stages.push_back(rec_);
}

// ---------------------------------------------------------------- the runner

Runner::Runner(StageList stages) {
  std::vector<std::string> names;
  for (const auto& s : stages) names.push_back(s->decl.name);
  auto indexOf = [&](const std::string& name) {
    const auto it = std::find(names.begin(), names.end(), name);
    return it == names.end() ? -1 : static_cast<int>(it - names.begin());
  };
  for (const auto& s : stages) {
    for (const std::string& up : s->decl.after)
      if (indexOf(up) < 0)
        throw Exception(fmt::format("stage {} runs after '{}', which is not a stage of this run",
                                    s->decl.name, up),
                        __FILE__, __LINE__, __func__);
    for (const std::string& o : s->decl.options)
      if (std::find(optionNames().begin(), optionNames().end(), o) == optionNames().end())
        throw Exception(fmt::format("stage {} declares unknown option '{}'", s->decl.name, o),
                        __FILE__, __LINE__, __func__);
  }
  // stable topological order: the first stage of the list whose upstream stages are all placed
  std::vector<bool> placed(stages.size(), false);
  while (stages_.size() < stages.size()) {
    bool progress = false;
    for (size_t i = 0; i < stages.size() && !progress; ++i) {
      if (placed[i]) continue;
      bool ready = true;
      for (const std::string& up : stages[i]->decl.after) ready = ready && placed[indexOf(up)];
      if (!ready) continue;
      placed[i] = true;
      progress = true;
      stages_.push_back(std::move(stages[i]));
    }
    if (!progress)
      throw Exception("pipeline stages: the `after` declarations form a cycle", __FILE__, __LINE__,
                      __func__);
  }
}

int Runner::unitCount(const Context& ctx, Unit unit) {
  switch (unit) {
    case Unit::View:
      return static_cast<int>(ctx.views.size());
    case Unit::Part:
      return static_cast<int>(ctx.parts.size());
    default:
      return 1;
  }
}

std::string Runner::entryName(const Context& ctx, const StageDecl& decl, int unit) {
  switch (decl.unit) {
    case Unit::View:
      return fmt::format("{}-{}", decl.name, unit);
    case Unit::Part:
      return decl.name + "-" + ctx.parts.at(unit).name;
    default:
      return decl.name;
  }
}

uint64_t Runner::unitKey(const Context& ctx, const StageDecl& decl, int unit,
                         const StageKeys& upstream,
                         std::map<std::string, uint64_t>& fileHashes) const {
  const RunInputs& in = ctx.in_;
  const std::string part = decl.unit == Unit::Part ? ctx.parts.at(unit).name : std::string();
  Hasher h;
  h.add(kKeyFormat)
      .add(std::string_view(decl.name))
      .add(decl.version)
      .add(unit)
      .add(std::string_view(part));
  const nlohmann::json& json = in.scene.desc.rawJson;
  for (const std::string& key : decl.scene) {
    h.add(std::string_view(key));
    // an absent key adds nothing: adding it changes the key, and a wildcard's absent members
    // (parts.{}.fixed of a part without `fixed`) leave it as it was
    for (const Pointer& at : expandKey(json, key, decl.unit, unit, part))
      if (json.contains(at)) {
        h.add(std::string_view(at.to_string()));
        hashJson(h, json.at(at), at, in.scene.desc.baseDir, fileHashes);
      }
  }
  for (const std::string& o : decl.options) {
    h.add(std::string_view(o));
    hashOption(h, in, o);
  }
  for (const std::string& f : decl.outputs)
    h.add(std::string_view(f)).add(hashFile(in.options.out / f));
  for (const std::string& up : decl.after) {
    const Stage* u = nullptr;
    for (const auto& s : stages_)
      if (s->decl.name == up) u = s.get();
    const std::vector<uint64_t>& keys = upstream.at(up);
    h.add(std::string_view(up));
    if (u->decl.unit == decl.unit && decl.unit != Unit::Global)
      h.add(keys.at(unit));  // the same view / part
    else
      for (uint64_t k : keys) h.add(k);
  }
  return h.digest();
}

StageKeys Runner::keys(const Context& ctx) const {
  StageKeys all;
  std::map<std::string, uint64_t> fileHashes;
  for (const auto& s : stages_) {
    std::vector<uint64_t>& k = all[s->decl.name];
    for (int u = 0; u < unitCount(ctx, s->decl.unit); ++u)
      k.push_back(unitKey(ctx, s->decl, u, all, fileHashes));
  }
  return all;
}

void Runner::run(Context& ctx) {
  StageKeys done;
  std::map<std::string, uint64_t> fileHashes;
  for (const auto& s : stages_) {
    std::vector<uint64_t>& k = done[s->decl.name];
    // keys as the stage starts: a file of the output folder it reads is as upstream stages left it
    for (int u = 0; u < unitCount(ctx, s->decl.unit); ++u)
      k.push_back(unitKey(ctx, s->decl, u, done, fileHashes));
    runStage(ctx, *s, k);
  }
}

void Runner::runStage(Context& ctx, Stage& stage, const std::vector<uint64_t>& keys) {
  const StageDecl& d = stage.decl;
  std::optional<StageScope> scope;
  if (d.cached)
    scope.emplace(ctx, d.row());
  else
    checkInterrupted();
  std::vector<int> missing;
  for (int u = 0; u < static_cast<int>(keys.size()); ++u) {
    if (!stage.applies(ctx, u)) continue;
    if (d.cached)
      if (auto hit = ctx.cache->load(entryName(ctx, d, u), keys[u])) {
        const Reads in(ctx, d, u);
        if (stage.load(ctx, in, u, *hit)) {
          scope->cached();
          continue;
        }
      }
    missing.push_back(u);
  }
  std::atomic<int> computed{0};
  auto computeUnit = [&](int u) {
    const Reads in(ctx, d, u);
    if (!stage.compute(ctx, in, u)) return false;
    if (d.cached) {
      Archive a;
      stage.save(ctx, u, a);
      ctx.cache->store(entryName(ctx, d, u), keys[u], a);
    }
    ++computed;
    return true;
  };
  if (d.parallel) {
    Progress progress(d.row(), static_cast<int64_t>(missing.size()));
    parallelFor(0, static_cast<int64_t>(missing.size()), [&](int64_t i) {
      if (interruptRequested()) return;
      if (computeUnit(missing[i])) progress.advance();
    });
    progress.finish();
  } else {
    for (int u : missing) {
      checkInterrupted();
      computeUnit(u);
    }
  }
  checkInterrupted();
  if (scope) scope->computed(computed);
  stage.finish(ctx, Reads(ctx, d, -1));
}

}  // namespace ps::pipeline
