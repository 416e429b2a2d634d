// glTF 2.0 export of a twin (spec ../shared/spec/scene-format.md section 3: OUT/twin.gltf,
// OUT/twin.bin): the whole scene with metallic-roughness PBR materials, normal maps and emitters.
//
// What is written:
// - one mesh (one primitive) per material part, with POSITION, NORMAL, TANGENT (optional) and
//   TEXCOORD_0; one glTF material per part. Window parts (environment.window_parts) are openings
//   and are left out unless `includeWindowParts` (then fully transparent).
// - The part's UV transform t = R(rot) * (S * uv) + offset is baked into TEXCOORD_0, flipped to
//   glTF's top-left origin: TEXCOORD_0 = (t_u, 1 - t_v). Maps repeat (REPEAT samplers), so the
//   maps themselves are referenced unchanged. TANGENT is dP/dt_u orthogonalised against the
//   normal, w = +1 where normal x tangent points along dP/dt_v (the OpenGL convention of our
//   normal maps, which is glTF's).
// - Textures are the twin folder's own files: textures/<part>_albedo.png (baseColorTexture, sRGB)
//   and textures/<part>_normal.png (normalTexture). glTF reads roughness from G and metallic from B
//   of one texture, so textures/<part>_metallic_roughness.png is written (roughness map times
//   roughness_scale, metallic map or value). An albedo map with albedo_offset != 0 or
//   albedo_scale > 1 is baked into textures/<part>_albedo_gltf.png; a pure scale <= 1 becomes
//   baseColorFactor. A part without maps gets baseColorFactor / roughnessFactor / metallicFactor
//   from its homogeneous values; a part with no materials file is the gray default.
// - homogeneous.specular != 0.5 becomes KHR_materials_specular (F0 = 0.08 * specular).
// - Emitters: a rectangle light is a two-triangle mesh facing normalize(edge_u x edge_v) with an
//   emissive black material; an OBJ-part emitter's material gets the emission. The radiance is
//   emissiveFactor * KHR_materials_emissive_strength (the extension only where a channel > 1).
// - World frame: meters; one root node "twin" rotates the scene's `up` onto glTF's +Y (identity
//   for up = +Y). Every file is written to a temporary name and renamed.
//
//   ps::Twin twin = ps::loadTwin("OUT");
//   ps::writeTwinGltf(twin, "OUT");     // OUT/twin.gltf, OUT/twin.bin,
//   OUT/textures/*_metallic_roughness.png
#pragma once

#include <filesystem>
#include <string>

#include "photoscene/scene/material.hpp"

namespace ps {

struct GltfExportOptions {
  bool exportTangents =
      true;  ///< write TANGENT for parts with a normal map (else viewers derive it)
  bool includeWindowParts = false;  ///< write window parts as fully transparent (alpha 0) meshes
  bool doubleSided = false;         ///< materials' doubleSided (emitters are always one-sided)
  std::string baseName = "twin";    ///< <baseName>.gltf and <baseName>.bin
};

/// What writeTwinGltf wrote (counts of the glTF's arrays).
struct GltfExportSummary {
  int meshes = 0, materials = 0, images = 0, emitters = 0;
  size_t binBytes = 0;
};

/// Writes outDir/twin.gltf + outDir/twin.bin (and the packed/baked textures under
/// outDir/textures/) for a loaded twin. Map files are referenced relative to outDir (normally
/// outDir == twin.dir). Throws ps::InputError when a materials file or map cannot be read,
/// ps::Exception when writing fails.
GltfExportSummary writeTwinGltf(const Twin& twin, const std::filesystem::path& outDir,
                                const GltfExportOptions& options = {});

}  // namespace ps
