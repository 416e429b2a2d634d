#include "photoscene/io/image_io.hpp"

#include <OpenImageIO/imageio.h>

#include <algorithm>

#include "photoscene/core/error.hpp"
#include "photoscene/core/image.hpp"
#include "photoscene/io/files.hpp"

namespace ps::io {

namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

std::unique_ptr<OIIO::ImageInput> openInput(const fs::path& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw InputError(path.string(), "", "image file not found");
  if (fs::is_directory(path, ec)) throw InputError(path.string(), "", "expected an image file, found a folder");
  // The reader is chosen by the file's extension and not by probing every format: faster on
  // damaged files and stricter (a .png must be a PNG).
  auto in = OIIO::ImageInput::create(path.string(), /*do_open=*/false);
  if (!in) {
    std::string why = OIIO::geterror();
    if (why.empty()) why = "unknown image format";
    throw InputError(path.string(), "", "cannot read the image (" + why + ")");
  }
  OIIO::ImageSpec spec;
  if (!in->open(path.string(), spec)) {
    std::string why = in->geterror();
    if (why.empty()) why = "not a valid " + std::string(in->format_name()) + " file";
    throw InputError(path.string(), "", "cannot read the image (" + why + ")");
  }
  return in;
}

/// Reads the pixels as stored: CV_8U, CV_16U or CV_32F with the file's channel count.
cv::Mat readRaw(const fs::path& path, ImageInfo* infoOut) {
  auto in = openInput(path);
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
    throw InputError(path.string(), "", "the image has no pixels");
  if (static_cast<int64_t>(spec.width) * spec.height > kMaxImagePixels)
    throw InputError(path.string(), "",
                     "expected an image of at most " + std::to_string(kMaxImagePixels / 1'000'000) +
                         " megapixels, but the header says " + std::to_string(spec.width) + "x" +
                         std::to_string(spec.height) + " (not decoded)");
  OIIO::TypeDesc readType = OIIO::TypeDesc::FLOAT;
  int depth = CV_32F;
  if (spec.format == OIIO::TypeDesc::UINT8) {
    readType = OIIO::TypeDesc::UINT8;
    depth = CV_8U;
  } else if (spec.format == OIIO::TypeDesc::UINT16) {
    readType = OIIO::TypeDesc::UINT16;
    depth = CV_16U;
  }
  const int cn = spec.nchannels;
  if (cn > 4) throw InputError(path.string(), "", "expected 1 to 4 channels, got " + std::to_string(cn));
  cv::Mat raw(spec.height, spec.width, CV_MAKETYPE(depth, cn));
  if (!in->read_image(0, 0, 0, cn, readType, raw.data)) {
    throw InputError(path.string(), "", "cannot decode the image (" + in->geterror() + ")");
  }
  if (infoOut) {
    infoOut->width = spec.width;
    infoOut->height = spec.height;
    infoOut->channels = cn;
    infoOut->bitsPerChannel = static_cast<int>(spec.format.size() * 8);
    infoOut->isFloat = spec.format.basetype == OIIO::TypeDesc::FLOAT ||
                       spec.format.basetype == OIIO::TypeDesc::HALF ||
                       spec.format.basetype == OIIO::TypeDesc::DOUBLE;
    infoOut->format = in->format_name();
  }
  return raw;
}

cv::Mat toFloatLinear(const cv::Mat& raw) {
  cv::Mat f;
  if (raw.depth() == CV_8U) raw.convertTo(f, CV_32F, 1.0 / 255.0);
  else if (raw.depth() == CV_16U) raw.convertTo(f, CV_32F, 1.0 / 65535.0);
  else f = raw;
  return f;
}

}  // namespace

ColorSpace parseColorSpace(const std::string& name) {
  const std::string n = lower(name);
  if (n == "srgb") return ColorSpace::SRGB;
  if (n == "linear") return ColorSpace::Linear;
  if (n == "auto" || n.empty()) return ColorSpace::Auto;
  PS_Check(false, "unknown color space '" << name << "' (expected srgb, linear or auto)");
  return ColorSpace::Auto;
}

ImageInfo readImageInfo(const fs::path& path) {
  auto in = openInput(path);
  const OIIO::ImageSpec& spec = in->spec();
  ImageInfo info;
  info.width = spec.width;
  info.height = spec.height;
  info.channels = spec.nchannels;
  info.bitsPerChannel = static_cast<int>(spec.format.size() * 8);
  info.isFloat = spec.format.basetype == OIIO::TypeDesc::FLOAT ||
                 spec.format.basetype == OIIO::TypeDesc::HALF ||
                 spec.format.basetype == OIIO::TypeDesc::DOUBLE;
  info.format = in->format_name();
  return info;
}

cv::Mat readImage(const fs::path& path, ColorSpace colorSpace) {
  ImageInfo info;
  cv::Mat raw = readRaw(path, &info);
  // Color channels only: gray(+alpha) -> gray, RGB(A) -> RGB.
  const int cn = raw.channels();
  std::vector<cv::Mat> planes;
  cv::split(raw, planes);
  cv::Mat rgb;
  if (cn <= 2) cv::merge(std::vector<cv::Mat>{planes[0], planes[0], planes[0]}, rgb);
  else cv::merge(std::vector<cv::Mat>{planes[0], planes[1], planes[2]}, rgb);
  const bool srgb = colorSpace == ColorSpace::SRGB ||
                    (colorSpace == ColorSpace::Auto && !info.isFloat);
  cv::Mat out = srgb ? srgbToLinear(rgb) : toFloatLinear(rgb);
  // Float files may hold NaN/Inf or negative values; the pipeline takes finite, non-negative light.
  if (info.isFloat) {
    cv::patchNaNs(out, 0.0);
    cv::max(out, 0.0, out);
    cv::min(out, 3.0e38, out);
  }
  return out;
}

cv::Mat readDataImage(const fs::path& path) {
  cv::Mat f = toFloatLinear(readRaw(path, nullptr));
  cv::patchNaNs(f, 0.0);
  return f.clone();
}

cv::Mat readLabelImage(const fs::path& path) {
  // The contract's label images are 8- or 16-bit PNGs (lossless: a lossy format would invent
  // labels along every edge). Checked before decoding: the label_image fuzzer found a file named
  // .png whose bytes OpenImageIO decoded as WebP, slowly.
  if (const std::string format = openInput(path)->format_name(); format != "png")
    throw InputError(path.string(), "", "expected an 8- or 16-bit PNG label image, got a " + format + " file");
  ImageInfo info;
  cv::Mat raw = readRaw(path, &info);
  if (info.isFloat || (raw.depth() != CV_8U && raw.depth() != CV_16U))
    throw InputError(path.string(), "",
                     "expected an 8- or 16-bit integer label image, got a " +
                         std::to_string(info.bitsPerChannel) + "-bit float image");
  if (raw.channels() != 1)
    throw InputError(path.string(), "",
                     "expected a single-channel label image, got " + std::to_string(raw.channels()) +
                         " channels");
  cv::Mat labels;
  raw.convertTo(labels, CV_32S);
  return labels;
}

namespace {
void writeWithOiio(const fs::path& path, const cv::Mat& data, OIIO::TypeDesc fileType, int quality) {
  writeAtomically(path, [&](const fs::path& tmp) {
    auto out = OIIO::ImageOutput::create(tmp.string());
    PS_Check(out, "no image writer for " << path << ": " << OIIO::geterror());
    OIIO::ImageSpec spec(data.cols, data.rows, data.channels(), fileType);
    if (quality > 0) spec.attribute("CompressionQuality", quality);
    if (lower(path.extension().string()) == ".exr") {
      spec.attribute("compression", "zip");
      // OIIO stamps EXRs with the current time unless told a DateTime: an empty one keeps the
      // same pixels byte-identical from run to run (issue 9, determinism)
      spec.attribute("DateTime", "");
    }
    PS_Check(out->open(tmp.string(), spec), "cannot open " << path << " for writing: " << out->geterror());
    OIIO::TypeDesc memType = data.depth() == CV_8U    ? OIIO::TypeDesc::UINT8
                             : data.depth() == CV_16U ? OIIO::TypeDesc::UINT16
                                                      : OIIO::TypeDesc::FLOAT;
    cv::Mat contiguous = data.isContinuous() ? data : data.clone();
    PS_Check(out->write_image(memType, contiguous.data), "cannot write " << path << ": " << out->geterror());
    PS_Check(out->close(), "cannot close " << path << ": " << out->geterror());
  });
}
}  // namespace

void writeImage(const fs::path& path, const cv::Mat& image, const WriteOptions& options) {
  PS_Check(!image.empty(), "writeImage(" << path << "): empty image");
  PS_Check(image.depth() == CV_32F && (image.channels() == 1 || image.channels() == 3 || image.channels() == 4),
           "writeImage(" << path << ") expects CV_32FC1/3/4, got " << typeName(image.type()));
  const std::string ext = lower(path.extension().string());
  const bool isFloatFormat = ext == ".exr" || ext == ".hdr";
  const bool isJpeg = ext == ".jpg" || ext == ".jpeg";
  PS_Check(isFloatFormat || isJpeg || ext == ".png" || ext == ".tif" || ext == ".tiff",
           "writeImage: unsupported extension '" << ext << "' (png, jpg, exr, hdr, tif)");
  cv::Mat clean = image.clone();
  cv::patchNaNs(clean, 0.0);
  if (isFloatFormat) {
    OIIO::TypeDesc type = ext == ".hdr" ? OIIO::TypeDesc::FLOAT
                          : options.bits == 32 ? OIIO::TypeDesc::FLOAT
                                               : OIIO::TypeDesc::HALF;
    if (options.encode == ColorSpace::SRGB) clean = linearToSrgb(clean, CV_32F);
    writeWithOiio(path, clean, type, 0);
    return;
  }
  const int bits = isJpeg ? 8 : (options.bits == 16 ? 16 : 8);
  const int depth = bits == 16 ? CV_16U : CV_8U;
  cv::Mat encoded;
  if (options.encode == ColorSpace::Linear) {
    cv::Mat clamped;
    cv::min(cv::max(clean, 0.0), 1.0, clamped);
    clamped.convertTo(encoded, depth, bits == 16 ? 65535.0 : 255.0);
  } else {
    encoded = linearToSrgb(clean, depth);
  }
  writeWithOiio(path, encoded, bits == 16 ? OIIO::TypeDesc::UINT16 : OIIO::TypeDesc::UINT8,
                isJpeg ? options.jpegQuality : 0);
}

void writeRawImage(const fs::path& path, const cv::Mat& image) {
  PS_Check(!image.empty(), "writeRawImage(" << path << "): empty image");
  PS_Check(image.depth() == CV_8U || image.depth() == CV_16U,
           "writeRawImage expects 8- or 16-bit, got " << typeName(image.type()));
  writeWithOiio(path, image, image.depth() == CV_16U ? OIIO::TypeDesc::UINT16 : OIIO::TypeDesc::UINT8, 0);
}

}  // namespace ps::io
