// Private: the parsed graph (GraphSpec) and its evaluator (forward with caching, reverse-mode
// backward), templated on the scalar type.
#pragma once

#include "node.hpp"
#include "photoscene/graph/material_graph.hpp"

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace ps::graphimpl {

struct LinkRef {
  int node = -1;  ///< index into GraphSpec::nodes; -1 = unlinked
  int port = 0;
};

struct NodeSpec {
  std::string id;
  const NodeType* type = nullptr;
  std::vector<double> constants;   ///< flat node parameter values from the file
  std::vector<LinkRef> inputs;     ///< per input port
  std::vector<int> inChannels;     ///< channels each input port expects (after resolution)
  std::vector<int> outChannels;    ///< per output port
  bool requiresGrad = false;       ///< a continuous exposed parameter here or upstream
  bool hasDiffBinding = false;     ///< a continuous exposed parameter targets this node
  std::vector<char> diffParam;     ///< per node parameter: a continuous exposed parameter targets it
};

struct Binding {
  int node = 0;
  int offset = 0;  ///< into the node's flat parameters
};

struct GraphSpec {
  std::string name, category, description, source;
  std::vector<NodeSpec> nodes;  ///< topologically sorted
  std::vector<GraphParameter> params;  ///< exposed; the last is albedo_offset
  std::vector<std::vector<Binding>> bindings;  ///< per exposed parameter
  std::array<LinkRef, kMapKindCount> outputs;
  int valueCount = 0;
  int albedoOffsetIndex = 0;  ///< offset of albedo_offset in the value vector
  uint64_t hash = 0;
};

/// Parses and validates graph JSON; throws ps::InputError naming `source`.
std::shared_ptr<const GraphSpec> parseGraph(const std::string& text, const std::string& source);

template <class T>
class Evaluator {
 public:
  explicit Evaluator(std::shared_ptr<const GraphSpec> spec) : spec_(std::move(spec)) {
    st_.resize(spec_->nodes.size());
    for (size_t i = 0; i < st_.size(); ++i) {
      const auto& ns = spec_->nodes[i];
      st_[i].params.assign(ns.constants.begin(), ns.constants.end());
    }
    values_.assign(spec_->valueCount, T(0));
  }

  const GraphSpec& spec() const { return *spec_; }
  int64_t runs() const { return runs_; }

  /// Flat graph values (already projected into their ranges).
  void setValues(const std::vector<double>& v) {
    PS_CheckEQ(int(v.size()), spec_->valueCount, "parameter vector length");
    for (size_t i = 0; i < v.size(); ++i) values_[i] = T(v[i]);
    for (size_t p = 0; p < spec_->params.size(); ++p)
      for (const Binding& b : spec_->bindings[p])
        for (int k = 0; k < spec_->params[p].dim; ++k)
          st_[b.node].params[b.offset + k] = values_[spec_->params[p].offset + k];
  }

  void clearCache() {
    for (auto& s : st_) s.valid = false;
  }

  /// Evaluates the requested maps; results in map(kind).
  void evaluate(int n, MapSet outputs) {
    PS_Check(n >= 4 && n <= 8192 && (n & (n - 1)) == 0, "size must be a power of two in [4, 8192], got " << n);
    n_ = n;
    requested_ = outputs;
    const auto& nodes = spec_->nodes;
    std::vector<char> needed(nodes.size(), 0);
    for (int k = 0; k < kMapKindCount; ++k)
      if (outputs.has(MapKind(k)) && spec_->outputs[k].node >= 0) needed[spec_->outputs[k].node] = 1;
    for (int i = int(nodes.size()) - 1; i >= 0; --i)
      if (needed[i])
        for (const LinkRef& l : nodes[i].inputs)
          if (l.node >= 0) needed[l.node] = 1;
    needed_ = needed;
    for (size_t i = 0; i < nodes.size(); ++i) {
      if (!needed[i]) continue;
      const NodeSpec& ns = nodes[i];
      auto& s = st_[i];
      Hasher h;
      h.add(n);
      h.add(s.params.data(), s.params.size() * sizeof(T));
      for (const LinkRef& l : ns.inputs) {
        h.add(l.node);
        if (l.node >= 0) h.add(st_[l.node].key);
      }
      const uint64_t key = h.digest();
      if (s.valid && s.key == key) continue;
      s.key = key;
      NodeCtx<T> c = makeCtx(int(i));
      for (size_t o = 0; o < ns.outChannels.size(); ++o) s.outs[o].create(n, ns.outChannels[o]);
      ns.type->forward<T>()(c);
      s.valid = true;
      ++runs_;
    }
    // final maps
    for (int k = 0; k < kMapKindCount; ++k) {
      if (!outputs.has(MapKind(k)) || spec_->outputs[k].node < 0) {
        final_[k].d.clear();  // keeps the buffer for the next evaluation
        final_[k].n = final_[k].c = 0;
        continue;
      }
      const Plane<T>& src = source(spec_->outputs[k]);
      Plane<T>& f = final_[k];
      if (k == int(MapKind::Albedo)) {
        f.create(n, 3);
        const T* off = &values_[spec_->albedoOffsetIndex];
        for (size_t p = 0; p < size_t(n) * n; ++p)
          for (int q = 0; q < 3; ++q) f.d[3 * p + q] = clamp01(src.d[p * src.c + (src.c == 1 ? 0 : q)] + off[q]);
      } else if (k == int(MapKind::Normal)) {
        f.create(n, 3);
        for (size_t p = 0; p < size_t(n) * n; ++p) {
          const T* a = &src.d[3 * p];
          const T l = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
          T* o = &f.d[3 * p];
          if (l < T(1e-12)) o[0] = 0, o[1] = 0, o[2] = 1;
          else o[0] = a[0] / l, o[1] = a[1] / l, o[2] = a[2] / l;
        }
      } else {
        f.create(n, 1);
        for (size_t p = 0; p < f.d.size(); ++p) f.d[p] = clamp01(src.d[p]);
      }
    }
  }

  const Plane<T>& map(MapKind k) const { return final_[int(k)]; }

  /// dMaps[k]: d loss / d final map k (nullptr = zero). Returns d loss / d values.
  std::vector<T> backward(const std::array<const Plane<T>*, kMapKindCount>& dMaps) {
    const auto& nodes = spec_->nodes;
    const int n = n_;
    std::vector<T> dv(spec_->valueCount, T(0));
    for (auto& s : st_) s.dActive = false;
    // gradient buffers are kept between calls up to 1024^2 (no allocation, no page faults per
    // backward); larger ones are freed as soon as their node is done to bound peak memory
    const bool keep = size_t(n) * n <= (size_t(1) << 20);
    auto dOutOf = [&](const LinkRef& l) -> Plane<T>& {
      auto& s = st_[l.node];
      if (!s.dActive) {
        s.dActive = true;
        s.dOuts.resize(nodes[l.node].outChannels.size());
        for (size_t o = 0; o < s.dOuts.size(); ++o) s.dOuts[o].zeros(n, nodes[l.node].outChannels[o]);
      }
      return s.dOuts[l.port];
    };
    for (int k = 0; k < kMapKindCount; ++k) {
      const Plane<T>* g = dMaps[k];
      const LinkRef& l = spec_->outputs[k];
      if (!g || l.node < 0 || final_[k].empty()) continue;
      PS_CheckEQ(g->d.size(), final_[k].d.size(), "gradient of map " << mapKindName(MapKind(k)));
      const Plane<T>& src = source(l);
      if (k == int(MapKind::Albedo)) {
        const T* off = &values_[spec_->albedoOffsetIndex];
        T* doff = &dv[spec_->albedoOffsetIndex];
        Plane<T>* d = nodes[l.node].requiresGrad ? &dOutOf(l) : nullptr;
        for (size_t p = 0; p < size_t(n) * n; ++p)
          for (int q = 0; q < 3; ++q) {
            const T raw = src.d[p * src.c + (src.c == 1 ? 0 : q)] + off[q];
            if (raw < 0 || raw > 1) continue;  // inclusive: one-sided slope at the bounds
            const T gg = g->d[3 * p + q];
            doff[q] += gg;
            if (d) d->d[p * src.c + (src.c == 1 ? 0 : q)] += gg;
          }
      } else if (!nodes[l.node].requiresGrad) {
        continue;
      } else if (k == int(MapKind::Normal)) {
        Plane<T>& d = dOutOf(l);
        for (size_t p = 0; p < size_t(n) * n; ++p) {
          const T* a = &src.d[3 * p];
          const T len = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
          if (len < T(1e-12)) continue;
          const T* gg = &g->d[3 * p];
          const T dot = (gg[0] * a[0] + gg[1] * a[1] + gg[2] * a[2]) / (len * len);
          for (int q = 0; q < 3; ++q) d.d[3 * p + q] += (gg[q] - a[q] * dot) / len;
        }
      } else {
        Plane<T>& d = dOutOf(l);
        for (size_t p = 0; p < d.d.size(); ++p)
          if (src.d[p] >= 0 && src.d[p] <= 1) d.d[p] += g->d[p];
      }
    }
    std::vector<std::vector<T>> dParams(nodes.size());
    for (int i = int(nodes.size()) - 1; i >= 0; --i) {
      const NodeSpec& ns = nodes[i];
      auto& s = st_[i];
      if (!needed_[i] || !ns.requiresGrad || !s.dActive) continue;
      NodeCtx<T> c = makeCtx(i);
      std::vector<Plane<T>>& bcastGrad = s.bcastGrad;
      bcastGrad.resize(ns.inputs.size());
      for (auto& b : bcastGrad) b.d.clear();
      c.dIn.assign(ns.inputs.size(), nullptr);
      for (size_t p = 0; p < ns.inputs.size(); ++p) {
        const LinkRef& l = ns.inputs[p];
        if (l.node < 0 || !nodes[l.node].requiresGrad) continue;
        Plane<T>& src = dOutOf(l);
        if (src.c != ns.inChannels[p]) {
          bcastGrad[p].zeros(n, ns.inChannels[p]);
          c.dIn[p] = &bcastGrad[p];
        } else {
          c.dIn[p] = &src;
        }
      }
      for (auto& d : s.dOuts) c.dOut.push_back(&d);
      dParams[i].assign(ns.type->valueCount, T(0));
      c.dParam = dParams[i].data();
      c.needParamGrad = ns.hasDiffBinding;
      c.wantParam = ns.diffParam.empty() ? nullptr : ns.diffParam.data();
      ns.type->backward<T>()(c);
      for (size_t p = 0; p < ns.inputs.size(); ++p) {
        if (bcastGrad[p].empty()) continue;
        Plane<T>& src = dOutOf(ns.inputs[p]);
        const int C = bcastGrad[p].c;
        for (size_t q = 0; q < src.d.size(); ++q)
          for (int k = 0; k < C; ++k) src.d[q] += bcastGrad[p].d[q * C + k];
      }
      s.dActive = false;
      if (!keep) {
        s.dOuts.clear();
        s.dOuts.shrink_to_fit();
        for (auto& b : bcastGrad) b = Plane<T>();
      }
    }
    for (size_t p = 0; p < spec_->params.size(); ++p) {
      const GraphParameter& gp = spec_->params[p];
      if (!gp.differentiable()) continue;
      for (const Binding& b : spec_->bindings[p])
        if (!dParams[b.node].empty())
          for (int k = 0; k < gp.dim; ++k) dv[gp.offset + k] += dParams[b.node][b.offset + k];
    }
    return dv;
  }

  /// The node's output plane (for tests).
  const Plane<T>& source(const LinkRef& l) const { return st_[l.node].outs[l.port]; }

 private:
  struct State {
    std::vector<T> params;
    std::vector<Plane<T>> outs, scratch, bcast, dOuts, bcastGrad;
    uint64_t key = 0;
    bool valid = false;
    bool dActive = false;  ///< dOuts hold this backward pass's gradients
  };

  NodeCtx<T> makeCtx(int i) {
    const NodeSpec& ns = spec_->nodes[i];
    auto& s = st_[i];
    NodeCtx<T> c;
    c.n = n_;
    c.param = s.params.data();
    c.poff = ns.type->offsets.data();
    c.scratch = &s.scratch;
    s.outs.resize(ns.outChannels.size());
    s.bcast.resize(ns.inputs.size());
    for (size_t p = 0; p < ns.inputs.size(); ++p) {
      const LinkRef& l = ns.inputs[p];
      if (l.node < 0) {
        c.in.push_back(nullptr);
        continue;
      }
      const Plane<T>& src = source(l);
      if (src.c == ns.inChannels[p]) {
        c.in.push_back(&src);
        continue;
      }
      Plane<T>& b = s.bcast[p];  // gray -> color broadcast
      const int C = ns.inChannels[p];
      b.create(n_, C);
      for (size_t q = 0; q < src.d.size(); ++q)
        for (int k = 0; k < C; ++k) b.d[q * C + k] = src.d[q];
      c.in.push_back(&b);
    }
    for (auto& o : s.outs) c.out.push_back(&o);
    return c;
  }

  std::shared_ptr<const GraphSpec> spec_;
  std::vector<State> st_;
  std::vector<T> values_;
  std::array<Plane<T>, kMapKindCount> final_;
  std::vector<char> needed_;
  MapSet requested_;
  int n_ = 0;
  int64_t runs_ = 0;
};

}  // namespace ps::graphimpl
