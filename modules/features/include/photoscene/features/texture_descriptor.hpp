// Masked multi-scale, multi-orientation texture descriptor (Gabor pyramid statistics).
//
// What is computed, for an image I (CV_32FC3, linear RGB) and a mask M (CV_8UC1, non-zero = in):
//
//  1. Crop to M's bounding box (origin aligned to 2^(numScales-1) pixels, so the result does not
//     depend on how much of the image around the region is passed in).
//  2. Luminance L = 0.2126 R + 0.7152 G + 0.0722 B; mu = mean of L over M;
//     Z0 = M * (L - mu): the region, centered, and exactly 0 outside the mask. Filtering Z0 with
//     zero padding therefore sees no edge where the mask ends, only the texture stopping, and
//     cropping changes nothing.
//  3. Pyramid: Z_{s+1} = even samples of blur(Z_s), blur = [1 4 6 4 1]/16 separable, zero border;
//     the mask goes down the same way as a coverage map M_s in [0, 1] (M_0 = M as 0/1).
//  4. At every level s and orientation theta_k = k * pi / numOrientations, a complex Gabor filter
//     g(x, y) = exp(-(x^2 + y^2) / (2 sigma^2)) * exp(i omega (x cos theta_k + y sin theta_k)),
//     omega = 2 pi centerFrequency, x to the right, y down (rows), its real part made zero-mean
//     by subtracting dc_k times the (normalized) envelope (the Morlet correction; it keeps the
//     even filter blind to the region's low frequencies). The envelope is isotropic, so
//     the filter is separable in complex arithmetic and a 90-degree image rotation maps
//     orientation k onto k + numOrientations / 2 exactly. Response r = a + i b (a: even / real,
//     b: odd / imaginary), then two fixed per-pixel gains (they depend on the mask only):
//       - unit band gain: divided by the pyramid blurs' attenuation at the band's center
//         frequency, so a unit-amplitude grating at a band's center gives |r| = 1 in that band;
//       - edge compensation: divided by sqrt(max(E_s, 0.1)), E_s the share of the filter's
//         energy |g|^2 that falls on the region (coverage M_s squared, filtered by the squared
//         envelope), so responses that straddle the mask's edge are not biased low (a thin strip
//         keeps its texture energy; the amplification is at most 3.16).
//     Magnitude |r| = sqrt(a^2 + b^2 + eps^2).
//  5. Masked statistics with weights w_s = M_s * C_s^boundaryPower, where C_s is the fraction of
//     the Gabor envelope (a Gaussian of the same sigma) that lies inside M_s. Pixels whose filter
//     support reaches outside the mask count less, smoothly; nothing is ever cut to zero weight,
//     so thin strips, holes and one-pixel masks still give finite, defined statistics.
//
// The descriptor (length 6 + 4 * numScales * numOrientations; 70 with the defaults), in order:
//   [0..2]   color mean:  masked mean of R, G, B                       (linear units)
//   [3..5]   color std:   masked sqrt(var + eps^2) of R, G, B         (linear units)
//   then for s = 0..numScales-1 (fine to coarse), k = 0..numOrientations-1, four entries:
//     meanRe  weighted mean of a                 (about 0 for most textures)
//     stdRe   weighted sqrt(var(a) + eps^2)      (band energy, "variance of responses")
//     meanMag weighted mean of |r|               (band energy, phase-invariant)
//     stdMag  weighted sqrt(var(|r|) + eps^2)    ("variance of magnitudes": how bursty the band is)
//   at index bandIndex(options, s, k) + {0, 1, 2, 3}.
// All entries are in the image's linear units (scale the image by c, every entry scales by |c|,
// up to eps). Use computeTextureKey() for a lighting-invariant vector.
//
// Example:
//   ps::TextureDescriptorOptions opt;                       // 4 scales x 4 orientations
//   ps::TextureDescriptor d = ps::computeTextureDescriptor(photo, partMask, opt);
//   float energy = d.values[ps::bandIndex(opt, 1, 2) + ps::kBandMeanMag];
//   std::vector<float> key = ps::computeTextureKey(photo, partMask);   // for FLANN
#pragma once

#include <opencv2/core.hpp>

#include <string>
#include <vector>

namespace ps {

/// Options of the filter bank and its statistics. Loss and key must use the same options as the
/// descriptors they are compared with.
struct TextureDescriptorOptions {
  /// Pyramid levels (octaves), >= 1. Level s sees periods of about 2^s / centerFrequency pixels.
  int numScales = 4;
  /// Orientations in [0, pi), >= 1; even counts make 90-degree rotations exact band shifts.
  int numOrientations = 4;
  /// Gabor center frequency in cycles per pixel of its level, in (0, 0.5): level s is tuned to
  /// periods of 4 * 2^s pixels with the default.
  double centerFrequency = 0.25;
  /// Gabor envelope standard deviation in pixels of its level. 1.5 with 0.25 gives a half-power
  /// bandwidth of about 1.6 octaves, so neighbouring octaves overlap and the energy of a grating
  /// moves smoothly between bands as its period changes (no gaps in the bank's response).
  double sigma = 1.5;
  /// Kernel half-width in sigmas (the kernel has 2 * ceil(kernelRadiusSigmas * sigma) + 1 taps).
  double kernelRadiusSigmas = 2.5;
  /// Exponent on the envelope-inside-mask fraction in the statistics' weights (0: plain mask).
  double boundaryPower = 2.0;
  /// Regularizer in magnitudes and standard deviations (linear units): keeps their gradients
  /// finite.
  double epsilon = 1e-5;

  bool IsValid(std::string* error) const;
};

/// Offsets of the four statistics within a band's entries.
enum TextureBandStat { kBandMeanRe = 0, kBandStdRe = 1, kBandMeanMag = 2, kBandStdMag = 3 };
/// Number of color entries at the start of the descriptor (mean R, G, B, std R, G, B).
inline constexpr int kTextureColorEntries = 6;

/// Length of the descriptor for these options: 6 + 4 * numScales * numOrientations.
int descriptorLength(const TextureDescriptorOptions& options);
/// Index of band (scale, orientation)'s first entry (its meanRe); add a TextureBandStat.
int bandIndex(const TextureDescriptorOptions& options, int scale, int orientation);

/// A descriptor with what was needed to read it.
struct TextureDescriptor {
  std::vector<float> values;  ///< descriptorLength(options) entries, layout above
  int numScales = 0;
  int numOrientations = 0;
  int maskPixels = 0;  ///< non-zero mask pixels
  /// Per scale: sum of the statistics' weights w_s, in level-0 pixels (weights * 4^s). Compare
  /// with maskPixels: a scale whose support is a small fraction of it rests on boundary pixels.
  std::vector<float> scaleSupport;
};

/// Computes the descriptor of the masked region.
/// @param image  CV_32FC3, linear RGB (R first), any non-negative scene-referred range; finite
/// @param mask   CV_8UC1, same size as image, non-zero = inside; must have at least one pixel
///               (an empty mask throws ps::Exception: a region without pixels has no texture)
/// @throws ps::Exception for a wrong type or size, a non-finite image, an empty mask or invalid
///         options
TextureDescriptor computeTextureDescriptor(const cv::Mat& image, const cv::Mat& mask,
                                           const TextureDescriptorOptions& options = {});

/// Options of the kNN key.
struct TextureKeyOptions {
  TextureDescriptorOptions descriptor;
  /// Group weights (each group's entries are also divided by sqrt(its size)). The anisotropy
  /// entries lie in [0, 1] while log contrasts span several units, hence its larger default
  /// (measured: it separates a 30-degree grating from a checker of the same period).
  float colorWeight = 1.0f;
  float contrastWeight = 1.0f;
  float anisotropyWeight = 2.0f;
  /// Floor inside the logarithms of relative contrasts (contrast below it reads as flat).
  float logFloor = 1e-3f;
  /// Weight of the joint statistics (texture_ps.hpp, pooled to be rotation-robust; see
  /// computeTextureKey). 0 = not part of the key (the default: the key is unchanged).
  float psWeight = 0.0f;

  bool IsValid(std::string* error) const;
};

/// Number of pooled joint-statistics entries the key gets when psWeight > 0:
/// 4 S + 2 S + S (K / 2) + (S - 1) (K / 2 + 1) + 5 (46 with the defaults).
int keyPsLength(const TextureDescriptorOptions& options);

/// Length of the key: 6 + 3 * numScales + numScales * (numOrientations / 2), plus keyPsLength
/// when psWeight > 0.
int keyLength(const TextureKeyOptions& options);

/// The lighting-invariant, rotation-robust key of a region, for a Euclidean kNN index.
///
/// Each channel is first divided by its interquartile mean over the mask (the mean of the values
/// between the 25th and 75th percentiles: the paper matches per-channel medians; the interquartile
/// mean is as robust to highlights and, unlike the median, does not jump between the two tones of
/// a two-tone texture as the region shifts), so lighting color and level (any positive per-channel
/// scale) leave the key unchanged, and the material's mean color is deliberately not part of it.
/// Then, from the descriptor of the normalized image (S = numScales, K = numOrientations):
///   [0..2]  log(std of normalized R, G, B + logFloor)        relative color contrast
///   [3..5]  correlation of (R, G), (G, B), (B, R) over the mask (in [-1, 1]; 0 if a channel is
///   flat) then per scale s (3 entries): log(orientation mean of meanMag + logFloor),
///           log(orientation mean of stdMag + logFloor), log(orientation mean of stdRe + logFloor)
///           -- orientation-pooled, hence rotation-invariant, relative band contrast
///   then per scale s (K/2 entries): |DFT_h| for h = 1..K/2 of the orientation profile
///           p_k = meanMag(s, k) / sum_k meanMag(s, k): the anisotropy (h = 1: one dominant
///           direction, h = 2: two at 90 degrees), invariant to any circular shift of the profile,
///           so exactly invariant to rotations by multiples of pi / K and smooth in between.
/// Then, only when psWeight > 0, the joint statistics of texture_ps.hpp (default lag windows) of
/// the normalized image, pooled so they do not depend on the texture's orientation (up to
/// multiples of 90 degrees):
///   per level (4): the low-pass autocorrelation averaged over the lags in rings of length
///           [1, 1.6), [1.6, 2.4), [2.4, 3.3), [3.3, 4.3) pixels of the level: periodicity
///   per level (2): the band magnitudes' autocorrelation averaged over orientations and the
///           rings [1, 1.6), [1.6, 2.9)
///   per level (K/2): cross-orientation correlation averaged over the pairs h = 1..K/2 apart
///   per level pair (K/2 + 1): cross-scale correlation averaged over (k, l) h = 0..K/2 apart
///   5: the opponent correlations (O1, O2), (O1, O3), (O2, O3), log(sd O1 / sd O3),
///      log(sd O2 / sd O3) (floors logFloor)
/// each group scaled by psWeight / sqrt(its size).
/// Groups are scaled by (weight / sqrt(group size)): color 6 entries, contrast 3S, anisotropy
/// S*K/2. With the defaults the key has 26 entries. The key is not unit length on purpose: the
/// log contrasts carry the absolute (relative-to-mean-level) texture strength.
/// Scale: a change of the texture's scale by a factor f moves energy between neighbouring
/// octaves smoothly (log2 f octaves); for retrieval under unknown scale, keep the key's scales and
/// let the bank hold each exemplar at a few scales (the UV search refines the rest).
///
/// @param image CV_32FC3, linear RGB, non-negative, finite
/// @param mask  CV_8UC1, same size, non-empty (an empty mask throws ps::Exception)
std::vector<float> computeTextureKey(const cv::Mat& image, const cv::Mat& mask,
                                     const TextureKeyOptions& options = {});

/// Euclidean distance between two equal-length vectors (descriptors or keys).
double descriptorDistance(const std::vector<float>& a, const std::vector<float>& b);

}  // namespace ps
