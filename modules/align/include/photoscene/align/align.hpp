// Material part masks and their alignment between the render of the coarse geometry and the
// photo (paper section 3.1).
//
//   M_geo    per part, where the rendered geometry shows the part (render frame)
//   M_photo  per part, where the photo shows it: label-image regions matched to parts by
//            maximum IoU (or pinned by the user), or, without labels, superpixels of the photo
//            merged to best cover each M_geo
//   Eq. (1)  x_s = (x_t - c_p) / l_p * l_g + c_g: the bounding-box affine map from a photo pixel
//            x_t to the render pixel x_s it takes its geometry from (c: box centers, l: box sizes)
//   M_aln    photo pixels of M_photo whose mapped render pixel lies in M_geo; the others have no
//            correspondence and are dropped, as in the paper
//
// Conventions: masks CV_8UC1 (0 / 255), part ids and labels CV_32SC1 (part id -1 = none,
// label 0 = unlabeled), photos CV_32FC3 linear RGB; pixel (x, y) is centered at (x, y).
#pragma once

#include <map>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace ps::align {

/// M_geo per part from a rendered part-id image.
/// @param partIds CV_32SC1, part id per pixel, -1 for background
/// @return part id -> CV_8UC1 mask (parts with at least `minPixels` pixels)
std::map<int, cv::Mat> partMasks(const cv::Mat& partIds, int minPixels = 1);

/// Intersection over union of two masks (0 when both are empty).
double iou(const cv::Mat& a, const cv::Mat& b);

struct MatchOptions {
  double minIou = 0.1;  ///< a region whose best IoU is below this stays unmatched
  bool IsValid(std::string* error) const;
};

struct RegionMatch {
  int label = 0;      ///< region value in the label image
  int part = -1;      ///< matched part, -1 when unmatched
  double iou = 0;     ///< IoU of the region with the part's M_geo (best IoU when unmatched)
  int bestPart = -1;  ///< part of the best IoU (also for unmatched regions)
  int pixels = 0;
  bool pinned = false;  ///< set by segment_parts
};

struct MatchResult {
  std::map<int, cv::Mat> photoMasks;  ///< part -> M_photo (union of its regions), CV_8UC1
  std::vector<RegionMatch> regions;   ///< every region of the label image, by label value
  std::vector<int> unmatched() const; ///< labels of regions left unmatched
};

/// Matches label-image regions to parts: pinned regions go to their part; every other region
/// goes to the part of maximum IoU with it when that IoU reaches minIou (a region goes to at most
/// one part; a part may collect several regions). M_geo masks must have the label image's size.
/// @param labels    CV_32SC1 label image, 0 = unlabeled
/// @param geoMasks  part -> M_geo (CV_8UC1, labels' size)
/// @param pinned    label value -> part (segment_parts)
MatchResult matchRegions(const cv::Mat& labels, const std::map<int, cv::Mat>& geoMasks,
                         const std::map<int, int>& pinned, const MatchOptions& options = {});

struct ProposalOptions {
  int superpixelSize = 16;  ///< SLIC region size (pixels) at 640 x 480, scaled with the image, >= 12
  float ruler = 12.0f;           ///< SLIC compactness
  double minCoverage = 0.5;      ///< a superpixel joins the part covering at least this fraction
  bool IsValid(std::string* error) const;
};

/// Proposes M_photo without a label image: SLIC superpixels of the photo (OpenCV ximgproc), each
/// given to the part whose M_geo covers the largest fraction of it (at least minCoverage), so
/// part boundaries snap to the photo's edges. Returns a label image (value = part id + 1, 0 =
/// unassigned) ready for matchRegions with every region pinned, and the pinned map.
/// @param photo CV_32FC3 linear RGB
cv::Mat proposeRegions(const cv::Mat& photo, const std::map<int, cv::Mat>& geoMasks,
                       std::map<int, int>* pinned, const ProposalOptions& options = {});

/// Axis-aligned bounding box of a mask's pixels in continuous coordinates: pixel centers are
/// integers, so a mask with pixels x0..x1 spans [x0 - 0.5, x1 + 0.5]. Empty rect for an empty mask.
cv::Rect2d maskBox(const cv::Mat& mask);

/// Eq. (1): the affine map taking photo-frame pixels x_t (in the box of `photoMask`) to
/// render-frame pixels x_s (in the box of `geoMask`): x_s = A x_t + b, returned as [A | b].
cv::Matx23d boxAffine(const cv::Mat& geoMask, const cv::Mat& photoMask);

/// The aligned part: M_aln and the render-frame buffers resampled into the photo frame.
struct AlignedPart {
  int part = -1;
  cv::Matx23d photoToRender;  ///< Eq. (1)
  cv::Mat mask;               ///< M_aln, CV_8UC1, photo frame
  std::vector<cv::Mat> buffers;  ///< the input buffers warped into the photo frame (same types)
  int photoPixels = 0;           ///< pixels of M_photo
  int droppedPixels = 0;         ///< M_photo pixels with no correspondence in M_geo
};

/// Warps a part's render-frame buffers into the photo frame with Eq. (1).
/// @param geoMask    M_geo (render frame, CV_8UC1)
/// @param photoMask  M_photo (photo frame, CV_8UC1; may differ in size from geoMask)
/// @param buffers    render-frame buffers (any type; continuous quantities such as UV or normals
///                   are sampled bilinearly, integer types with nearest neighbour), each the size
///                   of geoMask
AlignedPart alignPart(int part, const cv::Mat& geoMask, const cv::Mat& photoMask,
                      const std::vector<cv::Mat>& buffers);

/// An incomplete texture unwarped from the photo into texture space.
struct UnwarpedTexture {
  cv::Mat texture;    ///< CV_32FC3 linear RGB; row 0 is the top (largest v)
  cv::Mat coverage;   ///< CV_8UC1, 255 where photo pixels landed
  cv::Vec2d uvMin, uvMax;  ///< the UV rectangle the texture spans
  double texelsPerUv = 0;  ///< texels per UV unit (isotropic)
};

struct UnwarpOptions {
  double texelsPerPixel = 1.0;  ///< texture density relative to the photo's pixel footprint
  int maxSize = 1024;           ///< cap on the texture's larger side
  bool IsValid(std::string* error) const;
};

/// Splats the photo's pixels inside `mask` into texture space at their UVs (bilinear splatting,
/// normalized by weight). The density is chosen from the median UV footprint of a pixel.
/// @param photo CV_32FC3 linear RGB; @param uv CV_32FC2 (u, v), OBJ convention (v up), photo frame
/// @param mask CV_8UC1, photo frame (M_aln)
UnwarpedTexture unwarpToTexture(const cv::Mat& photo, const cv::Mat& uv, const cv::Mat& mask,
                                const UnwarpOptions& options = {});

/// Samples an unwarped texture at UVs (bilinear), the inverse of unwarpToTexture: for checking
/// and for showing what was recovered. Pixels outside the mask or the coverage are 0.
cv::Mat sampleTexture(const UnwarpedTexture& texture, const cv::Mat& uv, const cv::Mat& mask);

/// How well one view sees one part.
struct PartObservation {
  int view = 0;
  int pixels = 0;             ///< M_aln pixels
  double meanCosine = 0;      ///< mean |cos| between the surface normal and the view direction
  cv::Vec3f medianColor;      ///< per-channel median of the photo over M_aln (linear)
};

struct ViewChoice {
  int view = -1;
  std::vector<double> scores;     ///< per observation, same order
  std::vector<double> agreement;  ///< per observation, the appearance agreement in [0, 1]
  std::string reason;
};

/// Picks the view that sees a part best: score = pixels * meanCosine * agreement, where agreement
/// = exp(-d^2 / (2 * 0.25^2)) and d is the distance (in log color) of the view's median color,
/// divided by the view's exposure, from a reference color: a view whose appearance disagrees with
/// the others (highlight, occluder, mislabel) is down-weighted. The reference is the median over
/// views with three or more views; with two, the darker of the two (exposure-corrected luminance):
/// what brightens one view of a surface and not the other is mostly a highlight or glare, which a
/// diffuse fit must not follow; with one view, agreement is 1.
/// @param exposure per view (index = PartObservation::view); empty or shorter: 1
ViewChoice chooseView(const std::vector<PartObservation>& observations,
                      const std::vector<double>& exposure = {});

/// Relative exposures of `viewCount` views from the parts several of them see (before any light
/// is known): a Lambertian surface sends the same radiance to every camera, so the log ratio of
/// two views' median colours of one part is the log ratio of their exposures plus noise (other
/// pixels of the surface, highlights). Solves log e_v - log e_u = median over parts of the log
/// luminance differences, alternating with each part's log albedo, exposure[0] = 1. Views that
/// share no part (of at least `minPixels` M_aln pixels) with the others keep 1.
/// @param observations per part, its observations (any order; PartObservation::view set)
std::vector<double> estimateExposures(const std::vector<std::vector<PartObservation>>& observations,
                                      int viewCount, int minPixels = 50);

/// Per-channel median of `image` over `mask` (CV_32FC3, CV_8UC1).
cv::Vec3f maskedMedian(const cv::Mat& image, const cv::Mat& mask);

}  // namespace ps::align
