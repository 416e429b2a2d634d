// ps::MaterialGraph: the public face of a parsed graph and its float evaluator.
#include "engine.hpp"
#include "graph_access.hpp"

#include <cstring>
#include <fstream>
#include <sstream>

namespace ps {

using graphimpl::Evaluator;
using graphimpl::GraphSpec;
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
  for (size_t i = 0; i < parameters().size(); ++i) {
    const auto& p = parameters()[i];
    Rng r = rng.split(i);
    for (int k = 0; k < p.dim; ++k) {
      float& x = v[p.offset + k];
      if (p.name == "albedo_offset") {
        x = (r.uniform() * 0.2f - 0.1f) * spread;
      } else if (p.kind == ParameterKind::Continuous && p.dim == 3) {
        // colors: a plausible variation of the default (brightness and a little hue), not a
        // uniform RGB draw (which gives pastels no real material has)
        if (k == 0) r = rng.split(i + 1000);
        Rng rb = rng.split(i + 2000);
        const float bright = std::exp(spread * 0.7f * (rb.uniform() - 0.5f) * 2.f);
        x = x * bright * (1.f + spread * 0.3f * (r.uniform() - 0.5f) * 2.f);
      } else if (p.kind == ParameterKind::Continuous) {
        x = x + spread * (r.uniform(p.min, p.max) - x);
      } else {
        const float u = r.uniform();
        const float s = std::floor(r.uniform(p.min, p.max + 1.f));
        if (u < spread) x = std::min(s, p.max);
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
