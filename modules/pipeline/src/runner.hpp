// The stage runner: orders the stages by their declared dependencies, derives every unit's cache
// key from the declarations, loads what is unchanged, computes the rest, times each stage and
// records it in the stage table (private to the module; stage.hpp says what a stage declares).
#pragma once

#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "declared_keys.hpp"
#include "stage.hpp"

namespace ps::pipeline {

/// Every unit's cache key of every stage: keys[stage][unit].
using StageKeys = std::map<std::string, std::vector<uint64_t>>;

class Runner {
 public:
  /// Orders `stages` by their `after` (stable: the list order where it is free); throws
  /// ps::Exception naming a stage whose upstream stage is missing or that closes a cycle.
  explicit Runner(StageList stages);

  /// Runs every stage in order: keys, cache loads, computes (in parallel where declared),
  /// stores, `finish`, and the stage table (ctx.result.stages).
  void run(Context& ctx);

  /// The keys every unit of every stage has for the context's inputs; depends on the inputs and
  /// the declarations only (never on results), so it needs no stage to have run.
  StageKeys keys(const Context& ctx) const;

  const StageList& stages() const { return stages_; }
  /// The number of units a stage has in this run.
  static int unitCount(const Context& ctx, Unit unit);
  static std::string entryName(const Context& ctx, const StageDecl& decl, int unit);

 private:
  uint64_t unitKey(const Context& ctx, const StageDecl& decl, int unit, const StageKeys& upstream,
                   std::map<std::string, uint64_t>& fileHashes) const;
  /// The keys of every unit of the stage `decl` declares, added to `done` under its name.
  const std::vector<uint64_t>& addKeys(const Context& ctx, const StageDecl& decl, StageKeys& done,
                                       std::map<std::string, uint64_t>& fileHashes) const;
  void runStage(Context& ctx, Stage& stage, const std::vector<uint64_t>& keys);
  StageList stages_;
};

}  // namespace ps::pipeline
