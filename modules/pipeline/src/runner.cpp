// The stage runner (runner.hpp): the order, the cache, the stage table.
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

#include "photoscene/core.hpp"
#include "photoscene/core/memory.hpp"

namespace ps::pipeline {

namespace {

// Bump when the way keys are derived changes, so entries of older runs are not reused.
constexpr uint64_t kKeyFormat = 7;

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

namespace {

// Every upstream stage and option a stage declares exists.
void checkDeclarations(const StageList& stages) {
  for (const auto& s : stages) {
    for (const std::string& up : s->decl.after)
      if (std::none_of(stages.begin(), stages.end(),
                       [&](const auto& t) { return t->decl.name == up; }))
        throw Exception(fmt::format("stage {} runs after '{}', which is not a stage of this run",
                                    s->decl.name, up),
                        __FILE__, __LINE__, __func__);
    for (const std::string& o : s->decl.options)
      if (std::find(optionNames().begin(), optionNames().end(), o) == optionNames().end())
        throw Exception(fmt::format("stage {} declares unknown option '{}'", s->decl.name, o),
                        __FILE__, __LINE__, __func__);
  }
}

}  // namespace

// A stable topological order: each time, the first stage of the list whose upstream stages are
// all placed.
Runner::Runner(StageList stages) {
  checkDeclarations(stages);
  std::vector<std::string> placed;
  while (stages_.size() < stages.size()) {
    bool progress = false;
    for (auto& s : stages) {
      if (!s ||
          !std::all_of(s->decl.after.begin(), s->decl.after.end(), [&](const std::string& up) {
            return std::find(placed.begin(), placed.end(), up) != placed.end();
          }))
        continue;
      placed.push_back(s->decl.name);
      stages_.push_back(std::move(s));
      progress = true;
      break;
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
  const std::string part = decl.unit == Unit::Part ? ctx.parts.at(unit).name : std::string();
  Hasher h;
  h.add(kKeyFormat)
      .add(std::string_view(decl.name))
      .add(decl.version)
      .add(unit)
      .add(std::string_view(part));
  hashDeclaredInputs(h, ctx.in_, decl, unit, part, fileHashes);
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

const std::vector<uint64_t>& Runner::addKeys(const Context& ctx, const StageDecl& decl,
                                             StageKeys& done,
                                             std::map<std::string, uint64_t>& fileHashes) const {
  std::vector<uint64_t>& k = done[decl.name];
  for (int u = 0; u < unitCount(ctx, decl.unit); ++u)
    k.push_back(unitKey(ctx, decl, u, done, fileHashes));
  return k;
}

StageKeys Runner::keys(const Context& ctx) const {
  StageKeys all;
  std::map<std::string, uint64_t> fileHashes;
  for (const auto& s : stages_) addKeys(ctx, s->decl, all, fileHashes);
  return all;
}

void Runner::run(Context& ctx) {
  StageKeys done;
  std::map<std::string, uint64_t> fileHashes;
  // keys as each stage starts: a file of the output folder it reads is as upstream stages left it
  for (const auto& s : stages_) runStage(ctx, *s, addKeys(ctx, s->decl, done, fileHashes));
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
