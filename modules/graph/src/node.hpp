// Private: image planes, node kernel contexts and the node type registry.
//
// A node type is a forward and a backward kernel sharing one context (NodeCtx), templated on the
// scalar type (float for use, double for gradient checks). Kernels trust their inputs: the engine
// checks port channels and sizes once when a graph is loaded.
#pragma once

#include "photoscene/core.hpp"
#include "photoscene/graph/node_catalog.hpp"

#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace ps::graphimpl {

/// A square image of n x n pixels with c interleaved channels, row 0 at the top (t_v near 1).
template <class T>
struct Plane {
  int n = 0, c = 0;
  std::vector<T> d;
  void create(int n_, int c_) {
    n = n_;
    c = c_;
    d.resize(static_cast<size_t>(n) * n * c);
  }
  void zeros(int n_, int c_) {
    create(n_, c_);
    std::fill(d.begin(), d.end(), T(0));
  }
  T* row(int y) { return d.data() + static_cast<size_t>(y) * n * c; }
  const T* row(int y) const { return d.data() + static_cast<size_t>(y) * n * c; }
  T& at(int x, int y, int k = 0) { return d[(static_cast<size_t>(y) * n + x) * c + k]; }
  T at(int x, int y, int k = 0) const { return d[(static_cast<size_t>(y) * n + x) * c + k]; }
  T* ptr(int x, int y) { return d.data() + (static_cast<size_t>(y) * n + x) * c; }
  const T* ptr(int x, int y) const { return d.data() + (static_cast<size_t>(y) * n + x) * c; }
  bool empty() const { return d.empty(); }
};

/// The context of one kernel call. Forward reads `in`, `param` and writes every pixel of `out`
/// (pre-sized by the engine) and may keep what backward needs in `scratch`. Backward reads
/// `dOut` (never null, same shape as out) and ACCUMULATES into `dIn[k]` (null: not needed) and
/// `dParam` (never null, the node's flat parameter layout).
template <class T>
struct NodeCtx {
  int n = 0;                                ///< size in pixels (power of two)
  std::vector<const Plane<T>*> in;          ///< per input port; null for an unlinked optional port
  std::vector<Plane<T>*> out;               ///< per output port
  const T* param = nullptr;                 ///< flat parameter values
  const int* poff = nullptr;                ///< offset of parameter i in `param`
  std::vector<Plane<T>>* scratch = nullptr;  ///< node-private storage kept from forward to backward
  std::vector<const Plane<T>*> dOut;
  std::vector<Plane<T>*> dIn;
  T* dParam = nullptr;
  bool needParamGrad = true;                ///< false: dParam may be skipped
  const char* wantParam = nullptr;          ///< per parameter: 0 = its gradient may be skipped

  /// Whether d loss / d parameter i is needed (kernels may skip work that only feeds it).
  bool wantP(int i) const { return needParamGrad && (!wantParam || wantParam[i]); }

  T P(int i, int k = 0) const { return param[poff[i] + k]; }
  int I(int i) const { return static_cast<int>(std::lround(static_cast<double>(P(i)))); }
  T& dP(int i, int k = 0) { return dParam[poff[i] + k]; }
};

template <class T>
using Kernel = std::function<void(NodeCtx<T>&)>;

struct NodeType {
  NodeTypeDesc desc;
  std::vector<int> offsets;  ///< per parameter, into the flat vector
  int valueCount = 0;
  Kernel<float> forwardF, backwardF;
  Kernel<double> forwardD, backwardD;
  bool hasContinuous() const {
    for (const auto& p : desc.params)
      if (p.differentiable()) return true;
    return false;
  }
  int findParam(const std::string& name) const {
    for (size_t i = 0; i < desc.params.size(); ++i)
      if (desc.params[i].name == name) return static_cast<int>(i);
    return -1;
  }
  template <class T>
  const Kernel<T>& forward() const {
    if constexpr (std::is_same_v<T, float>) return forwardF;
    else return forwardD;
  }
  template <class T>
  const Kernel<T>& backward() const {
    if constexpr (std::is_same_v<T, float>) return backwardF;
    else return backwardD;
  }
};

/// Builds a NodeType from a kernel struct N with static desc(), forward<T>(ctx), backward<T>(ctx).
template <class N>
NodeType makeNodeType() {
  NodeType t;
  t.desc = N::desc();
  int off = 0;
  for (auto& p : t.desc.params) {
    p.offset = off;
    t.offsets.push_back(off);
    off += p.dim;
  }
  t.valueCount = off;
  t.forwardF = [](NodeCtx<float>& c) { N::template forward<float>(c); };
  t.forwardD = [](NodeCtx<double>& c) { N::template forward<double>(c); };
  t.backwardF = [](NodeCtx<float>& c) { N::template backward<float>(c); };
  t.backwardD = [](NodeCtx<double>& c) { N::template backward<double>(c); };
  return t;
}

/// Appends makeNodeType<N>() for every N in Ns.
template <class... Ns>
void addNodeTypes(std::vector<NodeType>& out) {
  (out.push_back(makeNodeType<Ns>()), ...);
}

/// The registry (built once, immutable).
const std::vector<NodeType>& nodeTypes();
const NodeType* findNodeType(const std::string& name);

// Registration lists, one per source file.
void addGeneratorNodes(std::vector<NodeType>& out);
void addFilterNodes(std::vector<NodeType>& out);

// ---- helpers for declaring parameters -------------------------------------------------------
inline GraphParameter pCont(const char* name, float lo, float hi, float def, const char* doc) {
  GraphParameter p;
  p.name = name;
  p.doc = doc;
  p.kind = ParameterKind::Continuous;
  p.min = lo;
  p.max = hi;
  p.defaultValue = {def};
  return p;
}
inline GraphParameter pColor(const char* name, float r, float g, float b, const char* doc) {
  GraphParameter p = pCont(name, 0.f, 1.f, r, doc);
  p.dim = 3;
  p.defaultValue = {r, g, b};
  return p;
}
inline GraphParameter pInt(const char* name, int lo, int hi, int def, const char* doc) {
  GraphParameter p = pCont(name, float(lo), float(hi), float(def), doc);
  p.kind = ParameterKind::Integer;
  return p;
}
inline GraphParameter pChoice(const char* name, std::vector<std::string> choices, int def,
                              const char* doc) {
  GraphParameter p = pInt(name, 0, int(choices.size()) - 1, def, doc);
  p.kind = ParameterKind::Choice;
  p.choices = std::move(choices);
  return p;
}
inline GraphParameter pSeed() { return pInt("seed", 0, 1 << 20, 0, "random seed"); }

// ---- kernel helpers --------------------------------------------------------------------------
inline uint32_t hash3(uint32_t a, uint32_t b, uint32_t c) {
  uint64_t x = (uint64_t(a) * 0x9E3779B1u) ^ (uint64_t(b) * 0x85EBCA77u << 1) ^
               (uint64_t(c) * 0xC2B2AE3Du << 2);
  return static_cast<uint32_t>(mix64(x) >> 16);
}
/// Uniform in [0, 1) from three integers.
inline float hashf(uint32_t a, uint32_t b, uint32_t c) {
  return static_cast<float>(hash3(a, b, c) >> 8) * 0x1p-24f;
}
template <class T>
inline T fracT(T x) {
  return x - std::floor(x);
}
template <class T>
inline T clamp01(T x) {
  return x < T(0) ? T(0) : (x > T(1) ? T(1) : x);
}
/// Row-parallel loop: body(y) for every row; rows in chunks so small images stay serial.
template <class F>
inline void forRows(int n, F&& body) {
  const int64_t grain = std::max<int64_t>(8, 16384 / std::max(1, n));
  if (n * n <= 64 * 64) {
    for (int y = 0; y < n; ++y) body(y);
    return;
  }
  ps::parallelForRanges(0, n, grain, [&](int64_t a, int64_t b) {
    for (int64_t y = a; y < b; ++y) body(static_cast<int>(y));
  });
}

/// Row-parallel loop over ranges: body(y0, y1) for consecutive rows [y0, y1), so a kernel can keep
/// per-range state (row caches) between rows.
template <class F>
inline void forRowRanges(int n, F&& body) {
  const int64_t grain = std::max<int64_t>(8, 16384 / std::max(1, n));
  if (n * n <= 64 * 64) {
    body(0, n);
    return;
  }
  ps::parallelForRanges(0, n, grain, [&](int64_t a, int64_t b) { body(int(a), int(b)); });
}

/// Bilinear sample of plane p at pixel coordinates (x, y) (pixel centers at integers), wrapping.
/// Writes c values to out; when gx/gy are non-null also the exact derivatives d/dx, d/dy.
template <class T>
inline void sampleBilinear(const Plane<T>& p, T x, T y, T* out, T* gx = nullptr, T* gy = nullptr) {
  const int n = p.n, c = p.c, m = n - 1;
  const T fx0 = std::floor(x), fy0 = std::floor(y);
  const T fx = x - fx0, fy = y - fy0;
  const int x0 = static_cast<int>(fx0) & m, y0 = static_cast<int>(fy0) & m;
  const int x1 = (x0 + 1) & m, y1 = (y0 + 1) & m;
  const T* a = &p.d[(size_t(y0) * n + x0) * c];
  const T* b = &p.d[(size_t(y0) * n + x1) * c];
  const T* cc = &p.d[(size_t(y1) * n + x0) * c];
  const T* dd = &p.d[(size_t(y1) * n + x1) * c];
  for (int k = 0; k < c; ++k) {
    const T top = a[k] + fx * (b[k] - a[k]);
    const T bot = cc[k] + fx * (dd[k] - cc[k]);
    out[k] = top + fy * (bot - top);
    if (gx) {
      gx[k] = (T(1) - fy) * (b[k] - a[k]) + fy * (dd[k] - cc[k]);
      gy[k] = bot - top;
    }
  }
  if (!gx) return;
  // exactly on a pixel center the bilinear derivative jumps; use the central difference (the
  // mean of the one-sided derivatives) so an offset of 0 still gets a gradient
  if (fx == T(0)) {
    const int xm = (x0 - 1) & m;
    const T* l0 = &p.d[(size_t(y0) * n + xm) * c];
    const T* l1 = &p.d[(size_t(y1) * n + xm) * c];
    for (int k = 0; k < c; ++k)
      gx[k] = T(0.5) * ((T(1) - fy) * (b[k] - l0[k]) + fy * (dd[k] - l1[k]));
  }
  if (fy == T(0)) {
    const int ym = (y0 - 1) & m;
    const T* u0 = &p.d[(size_t(ym) * n + x0) * c];
    const T* u1 = &p.d[(size_t(ym) * n + x1) * c];
    for (int k = 0; k < c; ++k) {
      const T vx0 = a[k] + fx * (b[k] - a[k]);
      const T vxp = cc[k] + fx * (dd[k] - cc[k]);
      const T vxm = u0[k] + fx * (u1[k] - u0[k]);
      gy[k] = T(0.5) * (vxp - vxm);
      (void)vx0;
    }
  }
}
/// Adjoint of sampleBilinear: scatters g (c values) into plane p.
template <class T>
inline void scatterBilinear(Plane<T>& p, T x, T y, const T* g) {
  const int n = p.n, c = p.c, m = n - 1;
  const T fx0 = std::floor(x), fy0 = std::floor(y);
  const T fx = x - fx0, fy = y - fy0;
  const int x0 = static_cast<int>(fx0) & m, y0 = static_cast<int>(fy0) & m;
  const int x1 = (x0 + 1) & m, y1 = (y0 + 1) & m;
  const T w00 = (1 - fx) * (1 - fy), w10 = fx * (1 - fy), w01 = (1 - fx) * fy, w11 = fx * fy;
  T* a = &p.d[(size_t(y0) * n + x0) * c];
  T* b = &p.d[(size_t(y0) * n + x1) * c];
  T* cc = &p.d[(size_t(y1) * n + x0) * c];
  T* dd = &p.d[(size_t(y1) * n + x1) * c];
  for (int k = 0; k < c; ++k) {
    a[k] += w00 * g[k];
    b[k] += w10 * g[k];
    cc[k] += w01 * g[k];
    dd[k] += w11 * g[k];
  }
}

}  // namespace ps::graphimpl
