// ps::paletteLoss (palette_prior.hpp).
#include "photoscene/graph/palette_prior.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "oklab.hpp"

namespace ps {

std::vector<std::vector<int>> paletteGroups(const MaterialGraph& graph, PaletteScope scope) {
  if (scope == PaletteScope::Ramps) return graph.colorRamps();
  std::vector<int> colours;
  const auto& params = graph.parameters();
  for (size_t i = 0; i < params.size(); ++i)
    if (params[i].dim == 3 && params[i].differentiable() && params[i].name != "albedo_offset")
      colours.push_back(static_cast<int>(i));
  if (colours.size() < 2) return {};
  return {colours};
}

double paletteLoss(const MaterialGraph& graph, const std::vector<float>& values,
                   std::vector<float>* grad, PaletteScope scope, float deadZone) {
  if (static_cast<int>(values.size()) != graph.valueCount())
    throw std::invalid_argument("paletteLoss: values must have valueCount() entries");
  if (grad) grad->assign(values.size(), 0.0f);
  const auto& params = graph.parameters();
  // the colours as the albedo shows them: each ramp colour plus the graph's albedo offset, clamped
  // as the albedo is (an offset of -0.19 on a dark brown turns it purple)
  const int offsetIndex = graph.findParameter("albedo_offset");
  const int aoff = offsetIndex >= 0 ? params[size_t(offsetIndex)].offset : -1;
  double loss = 0;
  for (const std::vector<int>& ramp : paletteGroups(graph, scope)) {
    const size_t n = ramp.size();
    std::vector<float> jac(9 * n);
    std::vector<char> inside(3 * n);
    std::vector<double> ca(n), cb(n), da(n), db(n);
    double mca = 0, mcb = 0, mda = 0, mdb = 0;
    for (size_t i = 0; i < n; ++i) {
      const GraphParameter& p = params[size_t(ramp[i])];
      float c[3], lab[3], lab0[3];
      for (int k = 0; k < 3; ++k) {
        const float x = values[size_t(p.offset + k)] + (aoff >= 0 ? values[size_t(aoff + k)] : 0.f);
        c[k] = std::clamp(x, 0.f, 1.f);
        inside[3 * i + k] = x > 0.f && x < 1.f;
      }
      graphimpl::linearToOklab(c, lab, &jac[9 * i]);
      graphimpl::linearToOklab(p.defaultValue.data(), lab0);
      ca[i] = lab[1], cb[i] = lab[2], da[i] = lab0[1], db[i] = lab0[2];
      mca += ca[i] / n, mcb += cb[i] / n, mda += da[i] / n, mdb += db[i] / n;
    }
    // each colour's residual r_i, its term (max(0, |r_i| - deadZone))^2 and that term's
    // derivative in r_i, (ga_i, gb_i)
    std::vector<double> ga(n), gb(n);
    double mga = 0, mgb = 0;
    for (size_t i = 0; i < n; ++i) {
      const double ra = (ca[i] - mca) - (da[i] - mda), rb = (cb[i] - mcb) - (db[i] - mdb);
      const double r = std::sqrt(ra * ra + rb * rb), excess = r - double(deadZone);
      if (deadZone <= 0) {
        loss += ra * ra + rb * rb;
        ga[i] = 2 * ra, gb[i] = 2 * rb;
      } else if (excess > 0) {
        loss += excess * excess;
        ga[i] = 2 * excess * ra / r, gb[i] = 2 * excess * rb / r;
      } else {
        ga[i] = gb[i] = 0;
      }
      mga += ga[i] / n, mgb += gb[i] / n;
    }
    if (!grad) continue;
    // r_i = c_i - mean c - const: d L / d c_j = g_j - mean_i g_i (the mean is 0 without a dead
    // zone, where the g_i are 2 r_i and the r_i sum to 0)
    for (size_t i = 0; i < n; ++i) {
      const double gai = ga[i] - mga, gbi = gb[i] - mgb;
      const float* J = &jac[9 * i];  // rows L, a, b; columns r, g, b
      const int off = params[size_t(ramp[i])].offset;
      for (int c = 0; c < 3; ++c) {
        const float g = inside[3 * i + c] ? float(gai * J[3 + c] + gbi * J[6 + c]) : 0.f;
        (*grad)[size_t(off + c)] += g;
        if (aoff >= 0) (*grad)[size_t(aoff + c)] += g;
      }
    }
  }
  return loss;
}

}  // namespace ps
