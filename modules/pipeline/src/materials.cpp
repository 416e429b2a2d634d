// The materials the path tracer renders with between stages: neutral (round 0) and fitted.
#include "stage.hpp"

namespace ps::pipeline {

std::vector<PartMaterial> neutralMaterials(const Context& ctx, const Reads& in) {
  std::vector<PartMaterial> mats;
  for (const PartWork& p : ctx.parts) {
    PartMaterial m = PartMaterial::defaultGray(p.name);
    if (p.mode == PartMode::Fixed) {
      const io::HomogeneousDesc& f = *in.partFixed(p.id);
      m.albedo = f.albedo.cast<float>();
      m.roughness = static_cast<float>(f.roughness);
      m.metallic = static_cast<float>(f.metallic);
      m.specular = static_cast<float>(f.specular);
    } else if (p.mode == PartMode::Emitter) {
      m.albedo = Vec3f::Zero();
    } else if (p.mode == PartMode::Fit || p.mode == PartMode::Homogeneous) {
      m.albedo = (p.median * ctx.albedoPin).cwiseMin(0.95f).cwiseMax(0.005f);
      m.roughness = 0.7f;
    }
    mats.push_back(std::move(m));
  }
  return mats;
}

HomogeneousFit fitHomogeneousPart(const Context& ctx, const Reads& in, const PartWork& p,
                                  const PartGeometry& geometry, const cv::Mat& photo,
                                  int candidates) {
  const std::vector<int> views = fitViews(p, in.fitAllViews());
  std::vector<PartGeometry> geos;
  geos.reserve(views.size());  // the PartViews point into it
  std::vector<PartView> pv = {{&geometry, photo, in.photoClip(p.view, ctx.viewExposure(p.view))}};
  for (size_t i = 1; i < views.size(); ++i) {
    const int w = views[i];
    const ViewWork& view = ctx.views[w];
    const auto mask = view.fitMask.find(p.id);
    if (mask == view.fitMask.end()) continue;
    geos.push_back(preparePartGeometry(view.gbuffer, in.camera(w).position().cast<float>(),
                                       view.grid, mask->second, p.id));
    if (geos.back().size() < kMinFitPixels) continue;
    pv.push_back({&geos.back(), partPhoto(in.photo(w), view, p.id) / ctx.viewExposure(w),
                  in.photoClip(w, ctx.viewExposure(w))});
  }
  return fitHomogeneous(pv, roughnessGrid(candidates), homogeneousRoughness(in.fitOptions()));
}

Vec3f meanAlbedo(const Context&, const Reads& in, const PartWork& p, Vec3f* mapMean) {
  if (p.mode != PartMode::Fit) return (p.albedo * p.albedoScale).cwiseMin(1.0f);
  MaterialGraph g = in.library().create(p.graph);
  g.setValues(p.values);
  const cv::Mat albedo = g.evaluate(in.fitOptions().mapSize, MapSet::of({MapKind::Albedo})).albedo;
  Vec3d sum = Vec3d::Zero(), raw = Vec3d::Zero();
  for (int y = 0; y < albedo.rows; ++y)
    for (int x = 0; x < albedo.cols; ++x) {
      const cv::Vec3f& t = albedo.at<cv::Vec3f>(y, x);
      const Vec3f m(t[0], t[1], t[2]);
      raw += m.cast<double>();
      sum += (p.albedoScale * (m + p.albedoOffset)).cwiseMax(0.0f).cwiseMin(1.0f).cast<double>();
    }
  const double n = std::max<double>(1, albedo.total());
  if (mapMean) *mapMean = (raw / n).cast<float>();
  return (sum / n).cast<float>();
}

std::vector<PartMaterial> fittedMaterials(const Context& ctx, const Reads& in, int mapSize) {
  std::vector<PartMaterial> mats = neutralMaterials(ctx, in);
  for (const PartWork& p : ctx.parts) {
    PartMaterial& m = mats[p.id];
    if (p.mode == PartMode::Homogeneous) {
      m.albedo = (p.albedo * p.albedoScale).cwiseMin(1.0f);
      m.roughness = std::clamp(p.roughness * p.roughnessFactor, 0.0f, 1.0f);
    } else if (p.mode == PartMode::Fit) {
      MaterialGraph g = in.library().create(p.graph);
      g.setValues(p.values);
      const MaterialMaps maps =
          g.evaluate(mapSize, MapSet::of({MapKind::Albedo, MapKind::Normal, MapKind::Roughness}));
      m.albedoMap = FloatTexture(maps.albedo);
      m.normalMap = FloatTexture(maps.normal);
      m.roughnessMap = FloatTexture(maps.roughness);
      m.uv = p.uv.toTransform();
      m.albedoScale = p.albedoScale;
      m.albedoOffset = p.albedoOffset;
      m.roughnessScale = p.roughnessScale * p.roughnessFactor;
      m.roughness = p.roughness;
      m.fromFile = true;
    }
  }
  return mats;
}

}  // namespace ps::pipeline
