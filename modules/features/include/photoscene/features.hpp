// photoscene features: masked, differentiable texture descriptors (the paper's VGG-19 feature loss
// and kNN key, replaced by classical filter-bank statistics; see ARCHITECTURE.md).
//
//   texture_descriptor.hpp  ps::TextureDescriptorOptions, computeTextureDescriptor() (the raw,
//                           fixed-length descriptor and its layout), computeTextureKey() (the
//                           lighting-invariant, rotation-robust key for the kNN index)
//   texture_loss.hpp        ps::TextureLossTarget (photo statistics, computed once),
//                           textureLossForward() / textureLossBackward() sharing
//                           ps::TextureLossParams, checkTextureLossGradient()
#pragma once

#include "photoscene/features/texture_descriptor.hpp"
#include "photoscene/features/texture_loss.hpp"
#include "photoscene/features/texture_structure.hpp"
