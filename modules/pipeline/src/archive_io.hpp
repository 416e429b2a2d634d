// Cache serialisation of the results the stages pass along (private to the module).
#pragma once

#include <vector>

#include "photoscene/pipeline/stage_cache.hpp"
#include "photoscene/raytrace.hpp"

namespace ps::pipeline {

void putVec3s(Archive& a, const std::vector<Vec3f>& v);
std::vector<Vec3f> getVec3s(Archive& a);
void putMats(Archive& a, const std::vector<cv::Mat>& v);
std::vector<cv::Mat> getMats(Archive& a);
void putGBuffer(Archive& a, const GBuffer& g);
GBuffer getGBuffer(Archive& a);
void putGrid(Archive& a, const IncidentLightGrid& g);
IncidentLightGrid getGrid(Archive& a);

}  // namespace ps::pipeline
