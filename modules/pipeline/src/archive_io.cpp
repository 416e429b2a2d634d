// Cache serialisation of G-buffers and incident-light grids (archive_io.hpp).
#include "archive_io.hpp"

namespace ps::pipeline {

void putVec3s(Archive& a, const std::vector<Vec3f>& v) {
  std::vector<float> f(v.size() * 3);
  for (size_t i = 0; i < v.size(); ++i)
    for (int c = 0; c < 3; ++c) f[3 * i + c] = v[i][c];
  a.putVector(f);
}

std::vector<Vec3f> getVec3s(Archive& a) {
  const std::vector<float> f = a.getVector<float>();
  std::vector<Vec3f> v(f.size() / 3);
  for (size_t i = 0; i < v.size(); ++i) v[i] = Vec3f(f[3 * i], f[3 * i + 1], f[3 * i + 2]);
  return v;
}

void putMats(Archive& a, const std::vector<cv::Mat>& v) {
  a.put<uint64_t>(v.size());
  for (const cv::Mat& m : v) a.putMat(m);
}

std::vector<cv::Mat> getMats(Archive& a) {
  std::vector<cv::Mat> v(a.get<uint64_t>());
  for (cv::Mat& m : v) m = a.getMat();
  return v;
}

void putGBuffer(Archive& a, const GBuffer& g) {
  for (const cv::Mat* m :
       {&g.partId, &g.triangleId, &g.uv, &g.duvdx, &g.duvdy, &g.position, &g.normalGeo,
        &g.normalShading, &g.tangent, &g.bitangent, &g.dpdu, &g.dpdv, &g.depth})
    a.putMat(*m);
  putMats(a, g.coverage);
  putMats(a, g.mask);
}

GBuffer getGBuffer(Archive& a) {
  GBuffer g;
  for (cv::Mat* m : {&g.partId, &g.triangleId, &g.uv, &g.duvdx, &g.duvdy, &g.position, &g.normalGeo,
                     &g.normalShading, &g.tangent, &g.bitangent, &g.dpdu, &g.dpdv, &g.depth})
    *m = a.getMat();
  g.coverage = getMats(a);
  g.mask = getMats(a);
  return g;
}

void putGrid(Archive& a, const IncidentLightGrid& g) {
  for (int v : {g.width, g.height, g.stride, g.thetaBins, g.phiBins}) a.put<int32_t>(v);
  putVec3s(a, g.radiance);
  a.putVector(g.valid);
  putVec3s(a, g.position);
  putVec3s(a, g.frameT);
  putVec3s(a, g.frameB);
  putVec3s(a, g.frameN);
  a.putVector(g.sensitivityStart);
  a.putVector(g.sensitivityPart);
  putVec3s(a, g.sensitivityValue);
}

IncidentLightGrid getGrid(Archive& a) {
  IncidentLightGrid g;
  for (int* v : {&g.width, &g.height, &g.stride, &g.thetaBins, &g.phiBins}) *v = a.get<int32_t>();
  g.radiance = getVec3s(a);
  g.valid = a.getVector<uint8_t>();
  g.position = getVec3s(a);
  g.frameT = getVec3s(a);
  g.frameB = getVec3s(a);
  g.frameN = getVec3s(a);
  g.sensitivityStart = a.getVector<int>();
  g.sensitivityPart = a.getVector<int>();
  g.sensitivityValue = getVec3s(a);
  return g;
}

}  // namespace ps::pipeline
