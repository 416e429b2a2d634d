// The inputs a stage declares, hashed: scene.json keys (a file by its bytes), options, files of
// the output folder (declared_keys.hpp).
#include "declared_keys.hpp"

#include <algorithm>

#include "photoscene/core.hpp"
#include "photoscene/eval.hpp"
#include "photoscene/pipeline/stage_cache.hpp"

namespace ps::pipeline {

namespace {

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
  else if (name == "eval_spp")
    h.add(o.evalSpp.value_or(-1));
  else if (name == "max_fit_iterations")
    h.add(o.maxFitIterations.value_or(-1));
  else if (name == "selection")
    if (o.selection) {
      const SynthesisOptions& s = *o.selection;
      h.add(1)
          .add(s.shortlist)
          .add(s.categories)
          .add(s.steps)
          .add(s.voteK)
          .add(s.homogeneous)
          .add(s.textureMargin)
          .add(s.maxPixelErrorRatio)
          .add(s.maxContrastRatio)
          .add(s.coarseContrastScale)
          .add(s.maxChromaRatio)
          .add(s.maxChromaOutside)
          .add(s.startFromNearestDraw)
          .add(s.warmStartFit)
          .add(s.heldOut)
          .add(s.minHeldOutPixels)
          .add(s.bandShape.value_or(-1.0f))
          .add(s.textureRequired)
          .add(s.heldParameters.size());
      for (const std::string& held : s.heldParameters) h.add(std::string_view(held));
    } else {
      h.add(0);
    }
  else if (name == "baseline")
    h.add(static_cast<int>(o.baseline));
  else if (name == "fit_views")
    h.add(o.fitAllViews);
  else if (name == "denoise")
    h.add(o.denoise);
  else if (name == "incident")
    h.add(o.incidentSamples.value_or(-1)).add(o.incidentDirectSamples.value_or(-1));
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

void hashDeclaredInputs(Hasher& h, const RunInputs& in, const StageDecl& decl, int unit,
                        const std::string& part, std::map<std::string, uint64_t>& fileHashes) {
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
}

}  // namespace ps::pipeline
