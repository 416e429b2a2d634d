// One view aligned: every part's M_photo, the Eq. (1) warp, M_aln in the render frame and the
// pixels the light solve may use; and how well a view sees a part (for chooseView).
//
//   const ps::align::ViewAlignment a = ps::align::alignView(photo, labels, pinned, gb.partId,
//   gb.coverage); cv::Mat mAln = a.fitMask.at(part);
#pragma once

#include <functional>
#include <map>
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "photoscene/align/align.hpp"
#include "photoscene/core/math.hpp"

namespace ps::align {

struct ViewAlignment {
  /// part -> M_photo (photo frame, CV_8UC1), for every part the label image matched, including
  /// parts with no M_geo or an empty M_photo (their warp is the identity and M_aln empty)
  std::map<int, cv::Mat> photoMask;
  std::map<int, cv::Matx23d> warp;   ///< part -> Eq. (1), photo -> render pixels
  std::map<int, cv::Mat> fitMask;    ///< part -> M_aln (render frame, CV_8UC1)
  cv::Mat lightMask;                 ///< CV_8UC1: where the photo region and the geometry agree
  std::vector<RegionMatch> regions;  ///< every region of the label image
};

/// Aligns one view: M_geo from the part ids (the interior of each part: coverage ~1), M_photo
/// from the label image (or regions proposed from the photo when it is empty), matched by IoU
/// with `pinned` regions first; per part the Eq. (1) box warp and M_aln = M_geo & warped M_photo
/// & interior (M_geo & warped M_photo for thin parts without interior). The light solve's mask
/// is M_geo & M_photo & interior, unwarped: the solve needs each pixel's own geometry.
/// @param photo    CV_32FC3 linear RGB (the render frame's size)
/// @param labels   CV_32SC1 regions, same size, or empty
/// @param pinned   region value -> part id (scene.json segment_parts)
/// @param partId   CV_32SC1 part id per pixel (-1: none), same size
/// @param coverage per part, CV_32FC1 fraction of the pixel it covers
ViewAlignment alignView(const cv::Mat& photo, const cv::Mat& labels,
                        const std::map<int, int>& pinned, const cv::Mat& partId,
                        const std::vector<cv::Mat>& coverage);

/// How a view sees a part through its M_aln: pixels, mean |cos| between the shading normal and
/// the direction to the camera, and the median colour; nothing when M_aln is empty. `view` is
/// left 0 for the caller to set.
/// @param partPhoto     CV_32FC3 the photo warped into the render frame for the part
/// @param fitMask       M_aln, CV_8UC1
/// @param normalShading CV_32FC3, @param position CV_32FC3 (world), same size
std::optional<PartObservation> observePart(const cv::Mat& partPhoto, const cv::Mat& fitMask,
                                           const cv::Mat& normalShading, const cv::Mat& position,
                                           const Vec3d& cameraPosition);

/// How a part's M_aln in one view (A) and in another (B) agree through the geometry (issue 19):
/// each pixel of A's M_aln is carried by its surface point (A's G-buffer position) into B. B sees
/// the point where it projects onto the part's interior there (the nearest pixel and its four
/// neighbours show the part) and B's surface point at that pixel is the same point (within 1.5 x
/// the largest distance from it to its neighbours' points: not another face of the part hiding
/// it). Of the points B sees, `inside` land in B's M_aln. A photo region matched to the wrong
/// place in one view, or a mask in the wrong frame, shows as a low share against the other views;
/// where the regions are the part's, Eq. (1)'s box warp keeps it near 1 (the coarse geometry's
/// error moves M_geo and M_aln together).
struct MaskConsistency {
  int pixels = 0;  ///< A's M_aln pixels
  int seen = 0;    ///< of them, those B sees on the part's interior
  int inside = 0;  ///< of those, the ones in B's M_aln
  /// inside / seen; -1 where B sees none of them
  double share() const { return seen > 0 ? static_cast<double>(inside) / seen : -1.0; }
};

/// Projects a world point into view B: false where it falls behind the camera; else its pixel
/// (x, y), pixel centres at integers.
using Projector = std::function<bool(const Vec3d& world, Vec2d* pixel)>;

/// MaskConsistency of `part` from view A to view B.
/// @param maskA, maskB         M_aln in A and in B (CV_8UC1, each in its view's render frame)
/// @param positionA, positionB CV_32FC3 world positions (the G-buffers of A and B)
/// @param partIdB              CV_32SC1 part ids of B's G-buffer
/// @param projectB             B's camera projection
MaskConsistency maskConsistency(int part, const cv::Mat& maskA, const cv::Mat& positionA,
                                const cv::Mat& maskB, const cv::Mat& positionB,
                                const cv::Mat& partIdB, const Projector& projectB);

}  // namespace ps::align
