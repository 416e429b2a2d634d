// Finite-difference gradient checks of graphs and node types, in float or double.
#include "photoscene/graph/gradient_check.hpp"

#include "engine.hpp"
#include "graph_access.hpp"

#include <sstream>

namespace ps {

using graphimpl::Evaluator;
using graphimpl::NodeCtx;
using graphimpl::Plane;

bool GradientCheckOptions::IsValid(std::string* error) const {
  auto bad = [&](const char* m) {
    if (error) *error = m;
    return false;
  };
  if (size < 4 || (size & (size - 1))) return bad("size must be a power of two >= 4");
  if (steps.empty()) return bad("steps must not be empty");
  for (double s : steps)
    if (!(s > 0)) return bad("steps must be positive");
  if (relTol < 0 || absTol < 0) return bad("tolerances must be >= 0");
  return true;
}

std::string GradientCheckReport::summary() const {
  std::ostringstream os;
  for (const auto& e : entries)
    if (!e.ok)
      os << e.parameter << ": analytic " << e.analytic << " vs finite difference "
         << e.finiteDifference << " (step " << e.step << ")\n";
  return os.str();
}

namespace {

/// Smooth periodic random field in [lo, hi] with c channels (a few random sinusoids).
template <class T>
Plane<T> smoothField(int n, int c, Rng& rng, double lo, double hi) {
  Plane<T> p;
  p.create(n, c);
  for (int k = 0; k < c; ++k) {
    double fx[4], fy[4], ph[4], a[4];
    for (int q = 0; q < 4; ++q) {
      fx[q] = double(rng.uniformInt(4));
      fy[q] = double(rng.uniformInt(4)) - 1.0;
      ph[q] = rng.uniform() * 6.283;
      a[q] = 0.5 + rng.uniform();
    }
    double asum = a[0] + a[1] + a[2] + a[3];
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const double u = (x + 0.5) / n, v = 1.0 - (y + 0.5) / n;
        double s = 0;
        for (int q = 0; q < 4; ++q) s += a[q] * std::sin(6.283185307 * (fx[q] * u + fy[q] * v) + ph[q]);
        p.at(x, y, k) = T(lo + (hi - lo) * (0.5 + 0.5 * s / asum));
      }
  }
  return p;
}

bool close(double a, double b, const GradientCheckOptions& o) {
  return std::abs(a - b) <= o.absTol + o.relTol * std::max(std::abs(a), std::abs(b));
}

template <class T>
GradientCheckReport checkGraphT(const MaterialGraph& graph, const GradientCheckOptions& o) {
  auto spec = GraphAccess::spec(graph);
  Evaluator<T> ev(spec);
  std::vector<double> values(graph.values().begin(), graph.values().end());
  ev.setValues(values);
  const int n = o.size;
  Rng rng(o.seed);
  std::array<Plane<T>, kMapKindCount> w;
  std::array<const Plane<T>*, kMapKindCount> wp{};
  const double inv = 1.0 / (double(n) * n);
  for (int k = 0; k < kMapKindCount; ++k) {
    if (!graph.hasOutput(MapKind(k))) continue;
    w[k] = smoothField<T>(n, k <= 1 ? 3 : 1, rng, -1.0 * inv, 1.0 * inv);
    wp[k] = &w[k];
  }
  auto loss = [&](const std::vector<double>& v) {
    ev.setValues(v);
    ev.evaluate(n, MapSet::all());
    double L = 0;
    for (int k = 0; k < kMapKindCount; ++k)
      if (wp[k]) {
        const auto& m = ev.map(MapKind(k));
        for (size_t i = 0; i < m.d.size(); ++i) L += double(m.d[i]) * double(w[k].d[i]);
      }
    return L;
  };
  loss(values);
  const std::vector<T> grad = ev.backward(wp);
  GradientCheckReport rep;
  for (const auto& p : graph.parameters()) {
    if (!p.differentiable()) continue;
    for (int k = 0; k < p.dim; ++k) {
      const int i = p.offset + k;
      const double range = p.max - p.min;
      GradientCheckEntry e;
      e.parameter = p.dim == 1 ? p.name : p.name + "[" + std::to_string(k) + "]";
      e.analytic = double(grad[i]) * range;
      for (double s : o.steps) {
        // central differences inside the range, one-sided at its ends (into the range)
        std::vector<double> vp = values, vm = values;
        double span = 2 * s;
        if (values[i] + s * range > p.max) {
          span = s;
        } else {
          vp[i] += s * range;
        }
        if (values[i] - s * range < p.min) span = s;
        else vm[i] -= s * range;
        if (vp[i] == vm[i]) vp[i] += s * range, span = s;  // degenerate range
        const double fd = (loss(vp) - loss(vm)) / span;
        if (!e.ok || s == o.steps.front()) e.finiteDifference = fd, e.step = s;
        if (close(e.analytic, fd, o)) {
          e.ok = true;
          e.finiteDifference = fd;
          e.step = s;
          break;
        }
      }
      rep.entries.push_back(e);
    }
  }
  return rep;
}

/// A kernel context of node type t over the planes `in` and `outs` with parameters `par`.
template <class T>
NodeCtx<T> nodeCtx(const graphimpl::NodeType& t, int n, const std::vector<Plane<T>>& in,
                   std::vector<Plane<T>>& outs, const std::vector<T>& par,
                   std::vector<Plane<T>>& scratch) {
  NodeCtx<T> c;
  c.n = n;
  for (const auto& p : in) c.in.push_back(&p);
  for (auto& p : outs) c.out.push_back(&p);
  c.param = par.data();
  c.poff = t.offsets.data();
  c.scratch = &scratch;
  return c;
}

template <class T>
GradientCheckReport checkNodeT(const graphimpl::NodeType& t, std::vector<double> params,
                               const GradientCheckOptions& o) {
  const int n = o.size;
  Rng rng(o.seed + 17);
  const auto& d = t.desc;
  int work = 3;
  for (const auto& p : d.inputs)
    if (p.channels == 1 && d.inputs.size() == 1) work = 1;
  std::vector<Plane<T>> ins, dirs;
  for (const auto& p : d.inputs) {
    const int c = p.channels == 0 ? work : p.channels;
    ins.push_back(smoothField<T>(n, c, rng, 0.05, 0.95));
    dirs.push_back(smoothField<T>(n, c, rng, -1.0, 1.0));
  }
  std::vector<Plane<T>> outs(d.outputs.size()), w(d.outputs.size()), scratch;
  for (size_t k = 0; k < d.outputs.size(); ++k) {
    const int c = d.outputs[k].channels == 0 ? work : d.outputs[k].channels;
    w[k] = smoothField<T>(n, c, rng, -1.0 / (double(n) * n), 1.0 / (double(n) * n));
  }
  std::vector<T> pv(params.begin(), params.end());
  auto run = [&](const std::vector<Plane<T>>& in, const std::vector<T>& par) {
    for (size_t k = 0; k < outs.size(); ++k) outs[k].create(n, w[k].c);
    NodeCtx<T> c = nodeCtx(t, n, in, outs, par, scratch);
    t.forward<T>()(c);
    double L = 0;
    for (size_t k = 0; k < outs.size(); ++k)
      for (size_t i = 0; i < outs[k].d.size(); ++i) L += double(outs[k].d[i]) * double(w[k].d[i]);
    return L;
  };
  run(ins, pv);
  std::vector<Plane<T>> dIn(ins.size());
  std::vector<T> dPar(pv.size(), T(0));
  {
    NodeCtx<T> c = nodeCtx(t, n, ins, outs, pv, scratch);
    for (auto& p : w) c.dOut.push_back(&p);
    for (size_t k = 0; k < ins.size(); ++k) {
      dIn[k].zeros(n, ins[k].c);
      c.dIn.push_back(&dIn[k]);
    }
    c.dParam = dPar.data();
    t.backward<T>()(c);
  }
  GradientCheckReport rep;
  auto check = [&](const std::string& name, double analytic, auto&& lossAt) {
    GradientCheckEntry e;
    e.parameter = name;
    e.analytic = analytic;
    for (double s : o.steps) {
      const double fd = (lossAt(s) - lossAt(-s)) / (2 * s);
      if (s == o.steps.front()) e.finiteDifference = fd, e.step = s;
      if (close(analytic, fd, o)) {
        e.ok = true, e.finiteDifference = fd, e.step = s;
        break;
      }
    }
    rep.entries.push_back(e);
  };
  for (const auto& p : d.params) {
    if (!p.differentiable()) continue;
    for (int k = 0; k < p.dim; ++k) {
      const int i = p.offset + k;
      const double range = p.max - p.min;
      check(p.dim == 1 ? p.name : p.name + "[" + std::to_string(k) + "]", double(dPar[i]) * range,
            [&](double s) {
              std::vector<T> q = pv;
              q[i] += T(s * range);
              return run(ins, q);
            });
    }
  }
  for (size_t k = 0; k < ins.size(); ++k) {
    double a = 0;
    for (size_t i = 0; i < dIn[k].d.size(); ++i) a += double(dIn[k].d[i]) * double(dirs[k].d[i]);
    check("input:" + d.inputs[k].name, a, [&](double s) {
      std::vector<Plane<T>> q = ins;
      for (size_t i = 0; i < q[k].d.size(); ++i) q[k].d[i] += T(s) * dirs[k].d[i];
      return run(q, pv);
    });
  }
  return rep;
}

}  // namespace

GradientCheckReport checkGraphGradients(const MaterialGraph& graph, const GradientCheckOptions& o) {
  std::string err;
  PS_Check(o.IsValid(&err), err);
  return o.doublePrecision ? checkGraphT<double>(graph, o) : checkGraphT<float>(graph, o);
}

GradientCheckReport checkNodeGradients(const std::string& nodeType,
                                       const std::vector<float>& paramValues,
                                       const GradientCheckOptions& o) {
  std::string err;
  PS_Check(o.IsValid(&err), err);
  const auto* t = graphimpl::findNodeType(nodeType);
  if (!t) throw InputError("", nodeType, "expected a node type name");
  std::vector<double> p;
  if (paramValues.empty()) {
    for (const auto& q : t->desc.params)
      for (float v : q.defaultValue) p.push_back(v);
  } else {
    PS_CheckEQ(int(paramValues.size()), t->valueCount, "parameter vector of node " << nodeType);
    p.assign(paramValues.begin(), paramValues.end());
  }
  return o.doublePrecision ? checkNodeT<double>(*t, p, o) : checkNodeT<float>(*t, p, o);
}

}  // namespace ps
