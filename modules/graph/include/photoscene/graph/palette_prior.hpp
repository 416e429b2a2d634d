// The palette prior: a colour ramp's colours keep the hue relations of the graph's defaults.
//
// A graph colours a pattern through a gradient_map whose two or three colours are exposed
// (MaterialGraph::colorRamps: wood's dark / mid / light, a brick's, a stone's). A texture loss
// that sees each colour channel's statistics, or the distribution of a few colour projections,
// can be matched by ramps no material has: red bricks fitted as pink and olive ones, a dark wood
// floor as deep red and brown stripes, a grey stone as green and purple (issue 18's coverage
// sheet). The random draws already keep ramps together (MaterialGraph::randomValues: a shared hue
// turn, small per-colour parts); the prior says the same to the fit. For each ramp, in Oklab's
// chroma plane (a, b):
//
//   L_palette = sum_ramps sum_i | (c_i - mean_j c_j) - (d_i - mean_j d_j) |^2
//
// c_i the chroma of the ramp's colour i at the current values as the albedo shows it (the colour
// plus the graph's albedo_offset, clamped to [0, 1]: an offset that matches the mean colour turns
// a ramp's dark end far more than its light end), d_i at the graph's defaults. The ramp's common
// chroma (its hue and saturation as a whole: brown to red, grey to beige) and every lightness are
// free; only how the colours differ from each other in chroma is held to the default's. Its
// gradient: d L / d c_i = 2 r_i (r_i the bracket; the means cancel because the r_i sum to 0),
// then through the Oklab Jacobian to the colour's and the offset's values (0 where the clamp
// holds). Units: Oklab chroma squared (a visible drift, pink against olive, is about 0.1 apart:
// L ~ 0.01).
//
//   std::vector<float> grad;
//   const double l = ps::paletteLoss(graph, values, &grad);  // 0 at graph.defaultValues()
#pragma once

#include <vector>

#include "photoscene/graph/material_graph.hpp"

namespace ps {

/// Which colours the prior holds together: each colour ramp (MaterialGraph::colorRamps), or all
/// the graph's colour parameters as one group (a grout, a joint or a speck colour with the
/// colours it sits among: a thin line takes any hue the texture statistics do not see, a purple
/// joint on a white panel).
enum class PaletteScope { Ramps, AllColours };

/// The groups `scope` names, as parameter indices (a group has at least two colours).
std::vector<std::vector<int>> paletteGroups(const MaterialGraph& graph, PaletteScope scope);

/// L_palette of `values` (length graph.valueCount()), summed over the groups of `scope`; 0 for a
/// graph without such a group. With `grad`, d L / d values (resized to valueCount(); 0 outside
/// the groups' colours and the albedo offset). Finite for every value in range, black included.
/// `deadZone` > 0: each colour's term is (max(0, |r_i| - deadZone))^2 instead of |r_i|^2, so that
/// departures as small as the graph's own random draws make cost nothing (kPaletteDrawDeadZone)
/// while a colour that leaves its group (a purple joint on a white panel) still does.
double paletteLoss(const MaterialGraph& graph, const std::vector<float>& values,
                   std::vector<float>* grad = nullptr, PaletteScope scope = PaletteScope::Ramps,
                   float deadZone = 0.0f);

/// The dead zone that covers the library's own draws: 99.9 % of every colour's |r_i| over all
/// the colours' group (PaletteScope::AllColours) of 64 draws per graph at the exemplar bank's
/// spread 0.6 is below 0.035 (Oklab chroma; 99 % below 0.021, the largest 0.070, fabric_tartan's
/// saturated stripes). SUN RGB-D's purple joint on a white ribbed panel (the fitted values of
/// 2026-12-07, offset included) was 0.067 from its default's relation to the panel's colours.
inline constexpr float kPaletteDrawDeadZone = 0.035f;

}  // namespace ps
