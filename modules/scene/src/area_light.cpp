// ps::AreaLight: an OBJ part or a rectangle emitting uniform radiance from one side.
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "light_geometry.hpp"
#include "photoscene/core/error.hpp"
#include "photoscene/scene/lights.hpp"
#include "photoscene/scene/mesh.hpp"

namespace ps {

AreaLight AreaLight::fromDesc(const io::AreaLightDesc& d, const std::vector<Part>& parts,
                              const std::string& file, const std::string& key) {
  AreaLight l;
  l.name = d.name;
  if (d.part) {
    l.kind = AreaLight::Kind::Part;
    l.partId = requirePartId(parts, *d.part, file, key + ".part");
  } else {
    l.kind = AreaLight::Kind::Rectangle;
    l.center = d.center.cast<float>();
    l.edgeU = d.edgeU.cast<float>();
    l.edgeV = d.edgeV.cast<float>();
  }
  if (d.radiance) l.radiance = d.radiance->cast<float>();
  return l;
}

std::unique_ptr<Light> AreaLight::fromJson(const io::JsonValue& entry,
                                           const LightJsonContext& ctx) {
  PS_Check(ctx.parts, "AreaLight::fromJson: no parts in the context");
  io::AreaLightDesc d = io::parseAreaLight(entry, false);
  if (d.name.empty()) d.name = d.part ? *d.part : "emitter";
  return std::make_unique<AreaLight>(fromDesc(d, *ctx.parts, entry.file(), entry.path()));
}

nlohmann::json AreaLight::toJson(const LightJsonContext& ctx) const {
  auto vec = [](const Vec3f& v) { return nlohmann::json{v.x(), v.y(), v.z()}; };
  nlohmann::json e;
  e["name"] = name;
  e["type"] = "area";
  if (kind == Kind::Part) {
    PS_Check(ctx.parts && partId >= 0 && partId < static_cast<int>(ctx.parts->size()),
             "area light '" << name << "': part " << partId << " not in the context's parts");
    e["part"] = (*ctx.parts)[partId].name;
  } else {
    e["center"] = vec(center);
    e["edge_u"] = vec(edgeU);
    e["edge_v"] = vec(edgeV);
  }
  e["radiance"] = vec(radiance.value_or(Vec3f::Zero()));
  return e;
}

std::vector<int> AreaLight::emittingParts() const {
  if (kind == Kind::Part && partId >= 0) return {partId};
  return {};
}

std::string AreaLight::describe(const std::vector<Part>& parts) const {
  const std::string what =
      kind == Kind::Part
          ? "part " + (partId >= 0 && partId < static_cast<int>(parts.size()) ? parts[partId].name
                                                                              : std::string("?"))
          : fmt::format("rectangle at ({:.2f}, {:.2f}, {:.2f}), {:.2f} m2", center.x(), center.y(),
                        center.z(), rectangleArea());
  const std::string rad = radiance ? fmt::format("radiance ({:.3g}, {:.3g}, {:.3g})", radiance->x(),
                                                 radiance->y(), radiance->z())
                                   : std::string("radiance to fit");
  return what + ", " + rad + (automatic ? " (automatic)" : "");
}

void AreaLight::shapes(std::vector<Vec3f>* v, std::vector<Vec3f>* normals) const {
  if (kind != Kind::Rectangle) return;
  if (normals) normals->insert(normals->end(), 6, normal());
  const Vec3f hu = 0.5f * edgeU, hv = 0.5f * edgeV;
  const Vec3f c[4] = {center - hu - hv, center + hu - hv, center + hu + hv, center - hu + hv};
  // winding so that (p1 - p0) x (p2 - p0) is along edgeU x edgeV
  for (int k : {0, 1, 2, 0, 2, 3}) v->push_back(c[k]);
}

void AreaLight::preprocess(const LightScene& scene) {
  tris_.clear();
  meshTriangles_.clear();
  sampled_.clear();
  if (kind == Kind::Part) {
    PS_Check(scene.mesh, "AreaLight::preprocess: no mesh");
    const Mesh& mesh = *scene.mesh;
    const bool owner = partId >= 0 && partId < static_cast<int>(scene.partEmitter.size()) &&
                       scene.partEmitter[partId] == scene.self;
    for (size_t t = 0; owner && t < mesh.numTriangles(); ++t) {
      if (mesh.partIds[t] != partId) continue;
      EmitterTriangle tri;
      if (!meshTriangle(mesh, static_cast<int>(t), &tri)) continue;
      // emits from the side its face normals point to: winding, or the OBJ normals when they
      // disagree
      const Vec3f nsum =
          mesh.cornerNormals[3 * t] + mesh.cornerNormals[3 * t + 1] + mesh.cornerNormals[3 * t + 2];
      if (nsum.dot(tri.n) < 0) tri.n = -tri.n;
      sampled_.push_back(static_cast<int>(tris_.size()));
      meshTriangles_.push_back(static_cast<int>(t));
      tris_.push_back(tri);
    }
  } else {
    std::vector<Vec3f> v;
    shapes(&v, nullptr);
    for (size_t k = 0; k + 2 < v.size(); k += 3) {
      EmitterTriangle tri;
      tri.p0 = v[k];
      tri.e1 = v[k + 1] - v[k];
      tri.e2 = v[k + 2] - v[k];
      tri.area = 0.5f * tri.e1.cross(tri.e2).norm();
      tri.n = normal();
      if (tri.area > 0 && tri.n.allFinite()) sampled_.push_back(static_cast<int>(tris_.size()));
      tris_.push_back(tri);
    }
  }
  std::vector<float> w;
  std::vector<const EmitterTriangle*> tp;
  for (int k : sampled_) {
    w.push_back(tris_[k].area);
    tp.push_back(&tris_[k]);
  }
  dist_ = Distribution1D(w);
  totalArea_ = dist_.total();
  rect_ = rectangleOf(tp);
}

float AreaLight::power(const Vec3f& scale) const {
  if (dist_.empty()) return 0;
  return luminanceOf(scale) * totalArea_;
}

bool AreaLight::sampleLi(const LightSampleContext& ctx, float, const Vec2f& uPt,
                         LightLiSample* ls) const {
  const Vec3f& x = ctx.p;
  const float selPdf = ctx.selectionPdf;
  const EmitterRectangle& R = rect_;
  Vec3f y, n;
  float pdfSA = -1;  // solid-angle pdf when sampled by solid angle
  if (R.valid) {
    n = R.n;
    if ((x - R.corner).dot(R.n) <= 0) return false;  // behind the one-sided emitter
    const SphericalRectangle sr(R.corner, R.ex, R.ey, x);
    if (useSpherical(sr)) {
      y = sr.sample(uPt.x(), uPt.y());
      pdfSA = selPdf / sr.solidAngle();
    } else {
      y = R.corner + uPt.x() * R.ex + uPt.y() * R.ey;
    }
  } else {
    if (dist_.empty()) return false;
    float triPdf = 0, ux = 0;
    const EmitterTriangle& tri = tris_[sampled_[dist_.sample(uPt.x(), &triPdf, &ux)]];
    y = pointOnTriangle(tri, ux, uPt.y());
    n = tri.n;
  }
  const Vec3f d = y - x;
  const float dist2 = d.squaredNorm();
  if (!(dist2 > 1e-12f)) return false;
  ls->dist = std::sqrt(dist2);
  ls->wi = d / ls->dist;
  const float cosl = -n.dot(ls->wi);
  if (cosl <= 1e-6f || ls->wi.dot(ctx.n) <= 0) return false;
  ls->pdf = pdfSA > 0 ? pdfSA : selPdf * dist2 / (totalArea_ * cosl);
  ls->L = Vec3f::Ones();
  if (!(ls->pdf > 0) || !std::isfinite(ls->pdf)) return false;
  // the shadow ray runs from org (x lifted off the surface) to y: measured from x, the segment
  // would end past an emitter a few cm away (the lift is ~1e-4 m) and shadow it
  return ctx.rays->unoccluded(ctx.org, y);
}

Vec3f AreaLight::L(const LightHit& hit) const {
  if (hit.primitive < 0 || hit.primitive >= static_cast<int>(tris_.size())) return Vec3f::Zero();
  const float cosl = -tris_[hit.primitive].n.dot(hit.dir);
  return cosl > 0 ? Vec3f(Vec3f::Ones()) : Vec3f(Vec3f::Zero());
}

float AreaLight::pdfLi(const LightSampleContext& ctx, const LightHit& hit) const {
  if (hit.primitive < 0 || hit.primitive >= static_cast<int>(tris_.size())) return 0;
  const float cosl = -tris_[hit.primitive].n.dot(hit.dir);
  if (!(cosl > 0)) return 0;
  if (rect_.valid) {
    const SphericalRectangle sr(rect_.corner, rect_.ex, rect_.ey, ctx.p);
    if (useSpherical(sr)) return ctx.selectionPdf / sr.solidAngle();
  }
  return ctx.selectionPdf * hit.t * hit.t / (totalArea_ * cosl);
}

// ---------------------------------------------------------------------------------------------

bool meshTriangle(const Mesh& mesh, int t, EmitterTriangle* tri) {
  const auto& f = mesh.triangles[t];
  tri->p0 = mesh.positions[f[0]];
  tri->e1 = mesh.positions[f[1]] - tri->p0;
  tri->e2 = mesh.positions[f[2]] - tri->p0;
  tri->area = mesh.area(t);
  tri->n = mesh.faceNormal(t);
  return tri->area > 0 && !tri->n.isZero();
}

EmitterRectangle rectangleOf(const std::vector<const EmitterTriangle*>& tris) {
  EmitterRectangle r;
  if (tris.size() != 2) return r;
  float scale = 0;
  for (const auto* t : tris)
    scale = std::max({scale, t->p0.cwiseAbs().maxCoeff(), (t->p0 + t->e1).cwiseAbs().maxCoeff(),
                      (t->p0 + t->e2).cwiseAbs().maxCoeff()});
  const float eps = 1e-5f * (1.0f + scale);
  std::vector<Vec3f> uniq;
  int idx[2][3];
  for (int k = 0; k < 2; ++k) {
    const auto* t = tris[k];
    const Vec3f v[3] = {t->p0, t->p0 + t->e1, t->p0 + t->e2};
    for (int j = 0; j < 3; ++j) {
      int found = -1;
      for (size_t u = 0; u < uniq.size(); ++u)
        if ((v[j] - uniq[u]).norm() <= eps) found = static_cast<int>(u);
      if (found < 0) {
        found = static_cast<int>(uniq.size());
        uniq.push_back(v[j]);
      }
      idx[k][j] = found;
    }
  }
  if (uniq.size() != 4) return r;
  // the shared diagonal: the two vertices both triangles use
  std::vector<int> shared;
  for (int j = 0; j < 3; ++j)
    if (std::find(idx[1], idx[1] + 3, idx[0][j]) != idx[1] + 3) shared.push_back(idx[0][j]);
  if (shared.size() != 2) return r;
  std::vector<int> other;
  for (int u = 0; u < 4; ++u)
    if (u != shared[0] && u != shared[1]) other.push_back(u);
  // corner c = other[0], its neighbours the diagonal's ends, opposite corner other[1]
  const Vec3f c = uniq[other[0]], ex = uniq[shared[0]] - c, ey = uniq[shared[1]] - c;
  if ((c + ex + ey - uniq[other[1]]).norm() > 4 * eps) return r;
  const float lx = ex.norm(), ly = ey.norm();
  if (!(lx > 0) || !(ly > 0) || std::abs(ex.dot(ey)) > 1e-4f * lx * ly) return r;
  const Vec3f n = ex.cross(ey).normalized();
  if (std::abs(n.dot(tris[0]->n)) < 0.999f || tris[0]->n.dot(tris[1]->n) < 0.999f) return r;
  r.corner = c;
  r.ex = ex;
  r.ey = ey;
  r.n = tris[0]->n;
  r.area = lx * ly;
  r.valid = true;
  return r;
}

}  // namespace ps
