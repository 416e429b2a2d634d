// photoscene features: masked, differentiable texture descriptors (the paper's VGG-19 feature loss
// and kNN key, replaced by classical filter-bank statistics; see ARCHITECTURE.md).
//
//   texture_descriptor.hpp  ps::TextureDescriptorOptions, computeTextureDescriptor() (the raw,
//                           fixed-length descriptor and its layout), computeTextureKey() (the
//                           lighting-invariant, rotation-robust key for the kNN index)
//   texture_loss.hpp        ps::TextureLossTarget (photo statistics, computed once),
//                           textureLossForward() / textureLossBackward() sharing
//                           ps::TextureLossParams, checkTextureLossGradient()
//   texture_ps.hpp          computeTexturePsStatistics(): Portilla-Simoncelli-style joint
//                           statistics (autocorrelations, cross-orientation / cross-scale
//                           magnitude correlations, opponent colour), optional loss terms
//   texture_contrast.hpp    typicalLocalContrast(): the median local contrast of a region (fine
//                           structure almost everywhere, not a few strong edges; model selection)
//   texture_pixel.hpp       pixelStructure(), pixelStructureLoss(): how the finest grain is
//                           correlated from pixel to pixel (white graph noise against a
//                           photograph's grain), with its gradient
//   texture_placement.hpp   ps::PlacementLossTarget, placementLoss(): the pattern's placement
//                           (low-passed luminance correlation, the paper's Eq. 9 pixel term)
#pragma once

#include "photoscene/features/texture_contrast.hpp"
#include "photoscene/features/texture_descriptor.hpp"
#include "photoscene/features/texture_loss.hpp"
#include "photoscene/features/texture_pixel.hpp"
#include "photoscene/features/texture_placement.hpp"
#include "photoscene/features/texture_ps.hpp"
#include "photoscene/features/texture_structure.hpp"
