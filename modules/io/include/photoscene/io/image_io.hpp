// Images through OpenImageIO: PNG, JPEG, EXR, HDR (and whatever else OIIO reads).
//
// Color: 8/16-bit files are sRGB-encoded unless told `ColorSpace::Linear`; float files (EXR, HDR)
// are linear. Everything returned is linear float, RGB order (not OpenCV's BGR), row 0 on top.
#pragma once

#include <cstdint>
#include <filesystem>
#include <opencv2/core.hpp>
#include <string>

namespace ps::io {

namespace fs = std::filesystem;

enum class ColorSpace {
  Auto,    ///< integer files are sRGB, float files linear
  SRGB,    ///< decode with the sRGB curve
  Linear,  ///< values are linear as stored (integers scaled to [0, 1])
};

/// Parses "srgb" | "linear" | "auto"; throws ps::Exception otherwise.
ColorSpace parseColorSpace(const std::string& name);

struct ImageInfo {
  int width = 0, height = 0, channels = 0;
  int bitsPerChannel = 0;  ///< 8, 16, 32 (or 16 for half)
  bool isFloat = false;
  std::string format;  ///< OIIO format name ("png", "openexr", ...)
};

/// The largest image (width x height) read: 100 megapixels. Checked from the header before any
/// pixel is decoded (a file claiming more is refused, whatever its real size), so no read
/// allocates more than 100 M x 4 channels x 4 bytes. Photos have a tighter, stated limit in
/// `loadScene` (what a run costs per photo pixel).
constexpr int64_t kMaxImagePixels = 100'000'000;

/// Reads only the header. Throws ps::InputError naming the file when missing or unreadable.
ImageInfo readImageInfo(const fs::path& path);

/// Reads a color image as CV_32FC3 linear RGB. Gray is replicated, alpha dropped.
/// Throws ps::InputError naming the file when missing, unreadable, with 0 or > 4 channels, or
/// larger than kMaxImagePixels (the reads below too).
cv::Mat readImage(const fs::path& path, ColorSpace colorSpace = ColorSpace::Auto);

/// Reads a data map with no color conversion: CV_32FC(n) with n the file's channel count;
/// 8-bit values divided by 255, 16-bit by 65535, float as stored (roughness, normal maps).
cv::Mat readDataImage(const fs::path& path);

/// Reads a label image (8- or 16-bit, one channel) as CV_32SC1; 0 = unlabeled.
/// Throws ps::InputError when the file has several channels or a float format.
cv::Mat readLabelImage(const fs::path& path);

struct WriteOptions {
  /// PNG: 8 or 16; EXR: 16 (half) or 32 (float); JPEG is always 8; HDR always float.
  int bits = 0;  ///< 0: 8 for PNG/JPEG, 16 (half) for EXR
  /// Auto: sRGB-encode for PNG/JPEG, linear for EXR/HDR. Linear stores values as they are
  /// (roughness and normal maps).
  ColorSpace encode = ColorSpace::Auto;
  int jpegQuality = 92;
};

/// Writes a CV_32FC1/3/4 image (linear values; RGB order) atomically (temporary name + rename).
void writeImage(const fs::path& path, const cv::Mat& image, const WriteOptions& options = {});

/// Writes a CV_8UC1/3 or CV_16UC1 image as stored (no color conversion), atomically.
void writeRawImage(const fs::path& path, const cv::Mat& image);

}  // namespace ps::io
