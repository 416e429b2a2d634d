// ps_bench_compare A.exr B.exr [--block N]
// Compares two linear images (the Cycles bench, bench/bench_cycles.sh). B is area-averaged to A's
// size when they differ. Prints one line of key=value:
//   rmse        sqrt(mean over pixels and channels of (a - b)^2), linear radiance
//   rmse_clip1  the same on min(x, 1) (display range: the emitters' 30x radiance does not dominate)
//   rel_l1      sum |a - b| / sum |b| over N x N-pixel box-filtered images (the Cycles test's metric)
//   mean_ratio  mean(a) / mean(b)
//   top1_share  share of the squared error in the 1 % of pixels with the largest error (fireflies)
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <functional>
#include <vector>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "photoscene/io/image_io.hpp"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s A B [--block N]\n", argv[0]);
    return 2;
  }
  int block = 4;
  for (int i = 3; i + 1 < argc; ++i)
    if (std::string(argv[i]) == "--block") block = std::atoi(argv[i + 1]);
  try {
    cv::Mat a = ps::io::readImage(argv[1], ps::io::ColorSpace::Linear);
    cv::Mat b = ps::io::readImage(argv[2], ps::io::ColorSpace::Linear);
    if (b.size() != a.size()) {
      cv::Mat r;
      cv::resize(b, r, a.size(), 0, 0, cv::INTER_AREA);
      b = r;
    }
    double se = 0, seClip = 0, sa = 0, sb = 0;
    std::vector<double> pixSe;
    pixSe.reserve(a.total());
    const double n = static_cast<double>(a.total()) * 3.0;
    for (int y = 0; y < a.rows; ++y)
      for (int x = 0; x < a.cols; ++x) {
        const cv::Vec3f pa = a.at<cv::Vec3f>(y, x), pb = b.at<cv::Vec3f>(y, x);
        double p = 0;
        for (int k = 0; k < 3; ++k) p += (pa[k] - pb[k]) * (pa[k] - pb[k]);
        pixSe.push_back(p);
        for (int k = 0; k < 3; ++k) {
          const double d = pa[k] - pb[k];
          const double dc = std::min(pa[k], 1.f) - std::min(pb[k], 1.f);
          se += d * d;
          seClip += dc * dc;
          sa += pa[k];
          sb += pb[k];
        }
      }
    cv::Mat ab, bb;
    cv::resize(a, ab, cv::Size(a.cols / block, a.rows / block), 0, 0, cv::INTER_AREA);
    cv::resize(b, bb, ab.size(), 0, 0, cv::INTER_AREA);
    double num = 0, den = 0;
    for (int y = 0; y < ab.rows; ++y)
      for (int x = 0; x < ab.cols; ++x)
        for (int k = 0; k < 3; ++k) {
          num += std::abs(ab.at<cv::Vec3f>(y, x)[k] - bb.at<cv::Vec3f>(y, x)[k]);
          den += std::abs(bb.at<cv::Vec3f>(y, x)[k]);
        }
    const size_t top = std::max<size_t>(1, pixSe.size() / 100);
    std::nth_element(pixSe.begin(), pixSe.begin() + top, pixSe.end(), std::greater<double>());
    double seTop = 0;
    for (size_t i = 0; i < top; ++i) seTop += pixSe[i];
    std::printf("rmse=%.6f rmse_clip1=%.6f rel_l1=%.5f mean_ratio=%.5f top1_share=%.3f mean_a=%.5f mean_b=%.5f size=%dx%d\n",
                std::sqrt(se / n), std::sqrt(seClip / n), num / den, sa / sb, se > 0 ? seTop / se : 0.0, sa / n, sb / n,
                a.cols, a.rows);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
  return 0;
}
