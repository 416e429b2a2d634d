// Stage `bounce`: the light that the fitted albedos bounce onto each other, made consistent.
//
// refine1 fits every part against grids traced with refine0's albedos (a1): the light a wall
// receives from the floor and the other walls is the light those old albedos reflect. The
// albedos it finds (a2) differ, and the final render, traced with a2, shows a2's bounced light,
// not a1's: in a bright room, where half a wall's light has bounced, a2 renders several percent
// off its photo, and alternating fit and grid again oscillates or diverges (each round's error
// is about minus the bounce share times the last). The grids also record what each point's
// irradiance owes to each part's albedo (IncidentLightGrid::albedoSensitivity), so to first
// order part i's light under albedos a is E_i(a1) prod_j (a_j / a1_j)^G_ij, with
// G_ij = (d E_i / d ln a_j) / E_i over the part's grid points. A render proportional to
// a_i E_i(a) matches the photo where a2 matched it under E_i(a1):
//
//   y_i + sum_j G_ij y_j = d_i,   y = ln(a / a1),  d = ln(a2 / a1),   per channel,
//
// one linear solve over the fitted parts (parts of given material, emitters and unseen parts
// keep their albedos: y = 0). Each part's mean albedo is then scaled by exp(y - d); a textured
// part keeps its pattern (albedo scale and offset move, the map does not).
#include <Eigen/Dense>
#include <fmt/format.h>
#include "photoscene/core/log.hpp"

#include <cmath>

#include "stages.hpp"

namespace ps::pipeline {

namespace {

class BounceStage : public Stage {
 public:
  BounceStage() : Stage("bounce") {
    decl.options = {"preset", "library", "work_width", "fit_views"};
    decl.after = {"parts", "observe", "select", "fit", "incident1", "refine1"};
    decl.writes = {"PartWork: homogeneous albedo, albedoScale, albedoOffset, bounceFactor"};
  }

  bool compute(Context& ctx, const Reads& in, int) override {
    std::vector<int> rowOf(ctx.parts.size(), -1), parts;
    for (const PartWork& p : ctx.parts)
      if ((p.mode == PartMode::Fit || p.mode == PartMode::Homogeneous) && p.view >= 0 &&
          p.gridAlbedo.minCoeff() > 0) {
        rowOf[p.id] = static_cast<int>(parts.size());
        parts.push_back(p.id);
      }
    const int n = static_cast<int>(parts.size());
    factor_.assign(ctx.parts.size(), Vec3f::Ones());
    if (n == 0) return true;
    // G per channel from the grid points on each part in the view it is fitted in
    std::vector<Eigen::MatrixXd> G(3, Eigen::MatrixXd::Zero(n, n));
    std::vector<Vec3d> light(n, Vec3d::Zero());
    bool recorded = false;
    for (int r = 0; r < n; ++r) {
      const PartWork& p = ctx.parts[parts[r]];
      const ViewWork& view = ctx.views[p.view];
      const IncidentLightGrid& g = view.grid;
      if (g.sensitivityStart.size() != g.valid.size() + 1) continue;
      recorded = true;
      const cv::Mat& ids = view.gbuffer.partId;
      for (int gy = 0; gy < g.height; ++gy)
        for (int gx = 0; gx < g.width; ++gx) {
          const size_t k = static_cast<size_t>(gy) * g.width + gx;
          if (!g.valid[k] || ids.at<int>(g.pixelY(gy, ids.rows), g.pixelX(gx, ids.cols)) != p.id)
            continue;
          light[r] += g.irradiance(gx, gy).cast<double>();
          for (int e = g.sensitivityStart[k]; e < g.sensitivityStart[k + 1]; ++e) {
            const int j = g.sensitivityPart[e];
            if (j < 0 || j >= static_cast<int>(rowOf.size()) || rowOf[j] < 0) continue;
            for (int c = 0; c < 3; ++c) G[c](r, rowOf[j]) += g.sensitivityValue[e][c];
          }
        }
    }
    if (!recorded) {
      spdlog::info("bounce: skipped: the grids carry no albedo sensitivity");
      return true;
    }
    std::vector<Vec3f> meanNow(n);
    for (int r = 0; r < n; ++r) meanNow[r] = meanAlbedo(ctx, in, ctx.parts[parts[r]]);
    double largest = 0;
    for (int c = 0; c < 3; ++c) {
      Eigen::VectorXd d(n);
      for (int r = 0; r < n; ++r) {
        const double e = light[r][c];
        G[c].row(r) = e > 0 ? Eigen::RowVectorXd(G[c].row(r) / e) : Eigen::RowVectorXd::Zero(n);
        const double now = std::max(1e-4f, meanNow[r][c]);
        d[r] = std::log(now / ctx.parts[parts[r]].gridAlbedo[c]);
      }
      const Eigen::MatrixXd A = Eigen::MatrixXd::Identity(n, n) + G[c];
      const Eigen::VectorXd y = A.colPivHouseholderQr().solve(d);
      if (!y.allFinite()) continue;
      for (int r = 0; r < n; ++r) {
        const double f = std::clamp(std::exp(y[r] - d[r]), kMinFactor, kMaxFactor);
        factor_[parts[r]][c] = static_cast<float>(f);
        largest = std::max(largest, std::abs(std::log(f)));
      }
    }
    std::string s;
    for (int id : parts)
      s += fmt::format(" {} ({:.3f}, {:.3f}, {:.3f})", ctx.parts[id].name, factor_[id][0],
                       factor_[id][1], factor_[id][2]);
    spdlog::info("bounce: albedo factors for the light the new albedos bounce:{} (largest {:.1f} %)",
                 s, 100 * (std::exp(largest) - 1));
    return true;
  }
  void save(const Context&, int, Archive& a) const override {
    std::vector<float> flat;
    for (const Vec3f& f : factor_) flat.insert(flat.end(), {f[0], f[1], f[2]});
    a.putVector(flat);
  }
  bool load(Context& ctx, const Reads&, int, Archive& a) override {
    const std::vector<float> flat = a.getVector<float>();
    if (flat.size() != 3 * ctx.parts.size()) return false;
    factor_.resize(ctx.parts.size());
    for (size_t i = 0; i < factor_.size(); ++i)
      factor_[i] = Vec3f(flat[3 * i], flat[3 * i + 1], flat[3 * i + 2]);
    return true;
  }
  // scales each part's mean albedo by its factor (after compute or load)
  void finish(Context& ctx, const Reads& in) override {
    for (size_t i = 0; i < factor_.size() && i < ctx.parts.size(); ++i) {
      PartWork& p = ctx.parts[i];
      const Vec3f& f = factor_[i];
      p.bounceFactor = f;
      if (f == Vec3f::Ones()) continue;
      if (p.mode == PartMode::Homogeneous) {
        p.albedo = p.albedo.cwiseProduct(f).cwiseMin(1.0f);
      } else if (p.mode == PartMode::Fit) {
        // scale(m + o) -> f (scale (m + o)) at the map's mean m: the scalar scale takes the mean
        // factor, the offset the rest of each channel
        Vec3f m;
        meanAlbedo(ctx, in, p, &m);
        const float mean = f.mean();
        p.albedoOffset = (m + p.albedoOffset).cwiseProduct(f / mean) - m;
        p.albedoScale *= mean;
      }
    }
  }

 private:
  // a first-order correction: a factor beyond these says the linearisation does not hold
  static constexpr double kMinFactor = 0.8, kMaxFactor = 1.25;
  std::vector<Vec3f> factor_;
};

}  // namespace

std::unique_ptr<Stage> makeBounceStage() {
  return std::make_unique<BounceStage>();
}

}  // namespace ps::pipeline
