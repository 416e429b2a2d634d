#include "photoscene/core/image.hpp"

#include <array>
#include <cmath>

#include "photoscene/core/error.hpp"

namespace ps {

float srgbToLinear(float v) {
  v = v < 0.f ? 0.f : (v > 1.f ? 1.f : v);
  if (v <= 0.04045f) return v / 12.92f;
  return static_cast<float>(std::pow((static_cast<double>(v) + 0.055) / 1.055, 2.4));
}

float linearToSrgb(float v) {
  v = v < 0.f ? 0.f : (v > 1.f ? 1.f : v);
  if (v <= 0.0031308f) return v * 12.92f;
  return static_cast<float>(1.055 * std::pow(static_cast<double>(v), 1.0 / 2.4) - 0.055);
}

namespace {
const std::array<float, 256>& decodeTable8() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) t[i] = srgbToLinear(i / 255.0f);
    return t;
  }();
  return table;
}
}  // namespace

cv::Mat srgbToLinear(const cv::Mat& src) {
  PS_Assert(!src.empty());
  const int cn = src.channels();
  cv::Mat dst(src.size(), CV_MAKETYPE(CV_32F, cn));
  const int depth = src.depth();
  PS_Check(depth == CV_8U || depth == CV_16U || depth == CV_32F,
           "unsupported depth " << typeName(src.type()));
  const auto& lut = decodeTable8();
  for (int y = 0; y < src.rows; ++y) {
    float* out = dst.ptr<float>(y);
    const int n = src.cols * cn;
    if (depth == CV_8U) {
      const uint8_t* in = src.ptr<uint8_t>(y);
      for (int i = 0; i < n; ++i) out[i] = lut[in[i]];
    } else if (depth == CV_16U) {
      const uint16_t* in = src.ptr<uint16_t>(y);
      for (int i = 0; i < n; ++i) out[i] = srgbToLinear(in[i] / 65535.0f);
    } else {
      const float* in = src.ptr<float>(y);
      for (int i = 0; i < n; ++i) out[i] = srgbToLinear(in[i]);
    }
  }
  return dst;
}

cv::Mat linearToSrgb(const cv::Mat& src, int depth) {
  PS_Assert(!src.empty());
  PS_CheckEQ(src.depth(), CV_32F, "linearToSrgb expects a float image, got " << typeName(src.type()));
  PS_Check(depth == CV_8U || depth == CV_16U || depth == CV_32F, "unsupported output depth");
  const int cn = src.channels();
  cv::Mat dst(src.size(), CV_MAKETYPE(depth, cn));
  for (int y = 0; y < src.rows; ++y) {
    const float* in = src.ptr<float>(y);
    const int n = src.cols * cn;
    if (depth == CV_8U) {
      uint8_t* out = dst.ptr<uint8_t>(y);
      for (int i = 0; i < n; ++i) {
        const float v = std::isfinite(in[i]) ? in[i] : 0.f;
        out[i] = static_cast<uint8_t>(std::lround(linearToSrgb(v) * 255.0f));
      }
    } else if (depth == CV_16U) {
      uint16_t* out = dst.ptr<uint16_t>(y);
      for (int i = 0; i < n; ++i) {
        const float v = std::isfinite(in[i]) ? in[i] : 0.f;
        out[i] = static_cast<uint16_t>(std::lround(linearToSrgb(v) * 65535.0f));
      }
    } else {
      float* out = dst.ptr<float>(y);
      for (int i = 0; i < n; ++i) out[i] = linearToSrgb(std::isfinite(in[i]) ? in[i] : 0.f);
    }
  }
  return dst;
}

std::string typeName(int type) {
  static const char* depths[] = {"8U", "8S", "16U", "16S", "32S", "32F", "64F", "16F"};
  const int depth = CV_MAT_DEPTH(type);
  return std::string("CV_") + depths[depth] + "C" + std::to_string(CV_MAT_CN(type));
}

void checkImage(const cv::Mat& m, int type, const char* what) {
  PS_Check(!m.empty(), what << " is empty");
  PS_Check(m.type() == type,
           what << " must be " << typeName(type) << ", got " << typeName(m.type()));
}

void checkImage(const cv::Mat& m, int type, cv::Size size, const char* what) {
  checkImage(m, type, what);
  PS_Check(m.size() == size, what << " must be " << size.width << "x" << size.height << ", got "
                                  << m.cols << "x" << m.rows);
}

bool allFinite(const cv::Mat& m) {
  if (m.empty()) return true;
  if (m.depth() != CV_32F && m.depth() != CV_64F) return true;
  return cv::checkRange(m, true, nullptr, -std::numeric_limits<double>::max(),
                        std::numeric_limits<double>::max());
}

}  // namespace ps
