// ps::MaterialGraph: the public face of a parsed graph and its float evaluator.
#include "engine.hpp"
#include "graph_access.hpp"
#include "oklab.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

namespace ps {

using graphimpl::Evaluator;
using graphimpl::GraphSpec;
using graphimpl::linearToOklab;
using graphimpl::oklabToLinear;
using graphimpl::Plane;

class GraphEngine {
 public:
  explicit GraphEngine(std::shared_ptr<const GraphSpec> s) : spec(s), eval(s) {
    for (const auto& p : spec->params)
      for (float v : p.defaultValue) values.push_back(v);
    push();
  }
  void push() { eval.setValues(std::vector<double>(values.begin(), values.end())); }
  std::shared_ptr<const GraphSpec> spec;
  Evaluator<float> eval;
  std::vector<float> values;
  std::array<Plane<float>, kMapKindCount> gradPlanes;  ///< reused by backward (no allocation per call)
};

cv::Mat& MaterialMaps::get(MapKind k) {
  switch (k) {
    case MapKind::Albedo: return albedo;
    case MapKind::Normal: return normal;
    case MapKind::Roughness: return roughness;
    case MapKind::Metallic: return metallic;
    default: return height;
  }
}
const cv::Mat& MaterialMaps::get(MapKind k) const { return const_cast<MaterialMaps*>(this)->get(k); }

MaterialGraph::MaterialGraph() = default;
MaterialGraph::MaterialGraph(MaterialGraph&&) noexcept = default;
MaterialGraph& MaterialGraph::operator=(MaterialGraph&&) noexcept = default;
MaterialGraph::~MaterialGraph() = default;

MaterialGraph MaterialGraph::fromString(const std::string& json, const std::string& sourceName) {
  MaterialGraph g;
  g.engine_ = std::make_unique<GraphEngine>(graphimpl::parseGraph(json, sourceName));
  return g;
}

MaterialGraph MaterialGraph::fromFile(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(path, "", "expected a readable graph file");
  std::stringstream ss;
  ss << f.rdbuf();
  return fromString(ss.str(), path);
}

MaterialGraph MaterialGraph::clone() const {
  MaterialGraph g;
  g.engine_ = std::make_unique<GraphEngine>(engine_->spec);
  g.engine_->values = engine_->values;
  g.engine_->push();
  return g;
}

const std::string& MaterialGraph::name() const { return engine_->spec->name; }
const std::string& MaterialGraph::category() const { return engine_->spec->category; }
const std::string& MaterialGraph::description() const { return engine_->spec->description; }
const std::string& MaterialGraph::source() const { return engine_->spec->source; }
uint64_t MaterialGraph::contentHash() const { return engine_->spec->hash; }
const std::vector<GraphParameter>& MaterialGraph::parameters() const { return engine_->spec->params; }
int MaterialGraph::valueCount() const { return engine_->spec->valueCount; }
int64_t MaterialGraph::nodeRuns() const { return engine_->eval.runs(); }

int MaterialGraph::findParameter(const std::string& name) const {
  const auto& p = parameters();
  for (size_t i = 0; i < p.size(); ++i)
    if (p[i].name == name) return int(i);
  return -1;
}

std::vector<std::vector<int>> MaterialGraph::colorRamps() const {
  const GraphSpec& spec = *engine_->spec;
  std::vector<std::pair<int, std::vector<int>>> ramps;  // (gradient_map node, its parameters)
  for (size_t i = 0; i < spec.params.size(); ++i) {
    const GraphParameter& p = spec.params[i];
    if (p.kind != ParameterKind::Continuous || p.dim != 3) continue;
    for (const graphimpl::Binding& b : spec.bindings[i]) {
      if (spec.nodes[size_t(b.node)].type->desc.name != "gradient_map") continue;
      auto it = std::find_if(ramps.begin(), ramps.end(), [&](const auto& r) { return r.first == b.node; });
      if (it == ramps.end()) ramps.push_back({b.node, {}}), it = ramps.end() - 1;
      if (std::find(it->second.begin(), it->second.end(), int(i)) == it->second.end())
        it->second.push_back(int(i));
    }
  }
  std::vector<std::vector<int>> out;
  for (auto& r : ramps)
    if (r.second.size() >= 2) out.push_back(std::move(r.second));
  return out;
}

std::vector<float> MaterialGraph::defaultValues() const {
  std::vector<float> v;
  for (const auto& p : parameters())
    for (float x : p.defaultValue) v.push_back(x);
  return v;
}

const std::vector<float>& MaterialGraph::values() const { return engine_->values; }

std::vector<float> MaterialGraph::projectValues(std::vector<float> v) const {
  PS_CheckEQ(int(v.size()), valueCount(), "parameter vector length of graph " << name());
  for (const auto& p : parameters())
    for (int k = 0; k < p.dim; ++k) {
      float& x = v[p.offset + k];
      if (!std::isfinite(x)) x = p.defaultValue[k];
      x = std::min(std::max(x, p.min), p.max);
      if (p.kind != ParameterKind::Continuous) x = std::round(x);
    }
  return v;
}

void MaterialGraph::setValues(const std::vector<float>& v) {
  engine_->values = projectValues(v);
  engine_->push();
}

void MaterialGraph::setParameter(const std::string& name, const std::vector<float>& value) {
  const int i = findParameter(name);
  PS_Check(i >= 0, "graph " << this->name() << " has no parameter " << name);
  const auto& p = parameters()[i];
  PS_CheckEQ(int(value.size()), p.dim, "dimension of parameter " << name);
  std::vector<float> v = engine_->values;
  std::copy(value.begin(), value.end(), v.begin() + p.offset);
  setValues(v);
}

std::vector<float> MaterialGraph::parameter(const std::string& name) const {
  const int i = findParameter(name);
  PS_Check(i >= 0, "graph " << this->name() << " has no parameter " << name);
  const auto& p = parameters()[i];
  return {values().begin() + p.offset, values().begin() + p.offset + p.dim};
}

std::vector<uint8_t> MaterialGraph::differentiableMask() const {
  std::vector<uint8_t> m(valueCount(), 0);
  for (const auto& p : parameters())
    if (p.differentiable())
      for (int k = 0; k < p.dim; ++k) m[p.offset + k] = 1;
  return m;
}

std::vector<float> MaterialGraph::randomValues(uint64_t seed, float spread) const {
  Rng rng(seed, 0x67726170ULL);
  std::vector<float> v = defaultValues();
  // one hue drift shared by all colours of the draw (the material as a whole turns a little
  // warmer or cooler), plus a smaller per-colour part
  Rng rh = rng.split(0x68756531ULL);
  const float sharedHue = spread * 0.20f * (rh.uniform() * 2.f - 1.f);  // radians in Oklab (a, b)
  // lightness and chroma mostly shared too, so colour ramps keep their order and contrast
  const float sharedLight = spread * 0.35f * (rh.uniform() * 2.f - 1.f);
  const float sharedChroma = spread * 0.3f * (rh.uniform() * 2.f - 1.f);
  // each parameter draws from its own stream; a parameter the draws never move (drawSpread 0)
  // takes none, so adding one to a graph leaves every other parameter's draw as it was
  // (albedo_offset keeps the default spread of 1)
  uint64_t stream = 0;
  for (size_t i = 0; i < parameters().size(); ++i) {
    const auto& p = parameters()[i];
    if (p.drawSpread <= 0.f) continue;
    Rng r = rng.split(stream++);
    if (p.name == "albedo_offset") {
      // mostly a gray shift: a per-channel offset turns dark materials green or pink
      const float gray = (r.uniform() * 0.12f - 0.06f) * spread;
      for (int k = 0; k < 3; ++k) v[p.offset + k] = gray + (r.uniform() * 0.02f - 0.01f) * spread;
      continue;
    }
    if (p.kind == ParameterKind::Continuous && p.dim == 3) {
      // colours: a plausible variation of the default in Oklab: lightness scaled, chroma scaled,
      // hue turned by a small angle (not a free RGB draw, which gives pastels no real material has)
      float* x = &v[p.offset];
      float lab[3];
      linearToOklab(x, lab);
      const float lightScale = std::exp(sharedLight + spread * 0.12f * (r.uniform() * 2.f - 1.f));
      const float chromaScale = std::exp(sharedChroma + spread * 0.12f * (r.uniform() * 2.f - 1.f));
      const float hue = sharedHue + spread * 0.08f * (r.uniform() * 2.f - 1.f);
      lab[0] = std::min(lab[0] * lightScale, 0.99f);
      const float ca = lab[1] * chromaScale, cb = lab[2] * chromaScale;
      lab[1] = ca * std::cos(hue) - cb * std::sin(hue);
      lab[2] = ca * std::sin(hue) + cb * std::cos(hue);
      float rgb[3];
      oklabToLinear(lab, rgb);
      for (int k = 0; k < 3; ++k) x[k] = std::isfinite(rgb[k]) ? rgb[k] : x[k];
      continue;
    }
    const float own = spread * p.drawSpread;
    for (int k = 0; k < p.dim; ++k) {
      float& x = v[p.offset + k];
      if (p.kind == ParameterKind::Continuous) {
        x = x + own * (r.uniform(p.min, p.max) - x);
      } else {
        const float u = r.uniform();
        const float s = std::floor(r.uniform(p.min, p.max + 1.f));
        if (u < own) x = std::min(s, p.max);
      }
    }
  }
  return projectValues(v);
}

bool MaterialGraph::hasOutput(MapKind kind) const {
  return engine_->spec->outputs[int(kind)].node >= 0;
}

MaterialMaps MaterialGraph::evaluate(int size, MapSet outputs) {
  engine_->eval.evaluate(size, outputs);
  MaterialMaps m;
  for (int k = 0; k < kMapKindCount; ++k) {
    const Plane<float>& p = engine_->eval.map(MapKind(k));
    if (p.empty()) continue;
    cv::Mat mat(p.n, p.n, CV_32FC(p.c));
    std::memcpy(mat.ptr<float>(), p.d.data(), p.d.size() * sizeof(float));
    m.get(MapKind(k)) = mat;
  }
  return m;
}

std::vector<float> MaterialGraph::backward(const MaterialMaps& dMaps) {
  auto& planes = engine_->gradPlanes;
  std::array<const Plane<float>*, kMapKindCount> ptrs{};
  for (int k = 0; k < kMapKindCount; ++k) {
    const cv::Mat& g = dMaps.get(MapKind(k));
    if (g.empty()) continue;
    const Plane<float>& f = engine_->eval.map(MapKind(k));
    PS_Check(!f.empty(), "backward: map " << mapKindName(MapKind(k)) << " was not evaluated");
    checkImage(g, CV_32FC(f.c), cv::Size(f.n, f.n), "backward gradient map");
    cv::Mat c = g.isContinuous() ? g : g.clone();
    planes[k].create(f.n, f.c);
    std::memcpy(planes[k].d.data(), c.ptr<float>(), planes[k].d.size() * sizeof(float));
    ptrs[k] = &planes[k];
  }
  std::vector<float> d = engine_->eval.backward(ptrs);
  for (float& x : d)
    if (!std::isfinite(x)) x = 0;
  return d;
}

void MaterialGraph::clearCache() { engine_->eval.clearCache(); }

std::shared_ptr<const graphimpl::GraphSpec> GraphAccess::spec(const MaterialGraph& g) {
  return g.engine_->spec;
}

}  // namespace ps
