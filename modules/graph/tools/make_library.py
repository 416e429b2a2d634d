#!/usr/bin/env python3
"""Writes the graph library (modules/graph/library/*.json) from compact Python descriptions.

The JSON files are the data the engine reads (format: ../FORMAT.md); this script is only a
convenience for maintainers. Users add graphs by writing JSON directly.
Run: python3 modules/graph/tools/make_library.py
"""
import json, os, struct

OUT = os.path.join(os.path.dirname(__file__), '..', 'library')
GRAPHS = []


class G:
    def __init__(self, name, category, description):
        self.name, self.category, self.description = name, category, description
        self.nodes, self.params, self.outputs = [], [], {}
        self.bands = []  # (fbm_bands node id, octaves) whose amplitudes done() exposes

    def n(self, id, type, inputs=None, **params):
        if type == 'fbm':
            type, params = 'fbm_bands', fbm_as_bands(id, params, self.bands)
        node = {'id': id, 'type': type}
        if params:
            node['params'] = params
        if inputs:
            node['inputs'] = inputs
        self.nodes.append(node)
        return id

    def p(self, name, *targets, doc='', **kw):
        # roughness / metallic levels outputs: their physical range, not the node's [-1, 2] (a
        # draw outside [0, 1] clamps the map and leaves the parameter without gradient)
        if (name.startswith('roughness') or name.endswith('metallic')) and 'min' not in kw and 'max' not in kw:
            kw['min'], kw['max'] = 0.0, 1.0
        d = {'name': name, 'targets': list(targets)}
        if doc:
            d['doc'] = doc
        d.update(kw)
        self.params.append(d)

    def out(self, **o):
        self.outputs.update(o)

    def done(self):
        for id, octaves in self.bands:
            if octaves < 2:
                continue  # one octave: its amplitude cancels in the normalisation
            for k in range(octaves):
                self.p('grain_%s_%d' % (id, k), '%s.band_%d' % (id, k), min=0.0, max=1.0, draw_spread=0.0,
                       doc='amplitude of octave %d of noise %s (relative to its other octaves)' % (k, id))
        GRAPHS.append(self)

    def json(self):
        return {'name': self.name, 'category': self.category, 'description': self.description,
                'nodes': self.nodes, 'parameters': self.params, 'outputs': self.outputs}


def f32(x):
    """x rounded to the nearest 32-bit float (the engine's parameter type)."""
    return struct.unpack('f', struct.pack('f', x))[0]


def fbm_as_bands(id, params, bands):
    """An fbm node's parameters as fbm_bands' (band_k = roughness^k: the same noise), the node
    recorded in `bands` so that the fit can shape each octave's amplitude (issue 18: the
    photographs' spectra are not the power law that one roughness gives)."""
    octaves, r = params.get('octaves', 5), params.get('roughness', 0.5)
    out = {'scale_x': params.get('scale_x', 4), 'scale_y': params.get('scale_y', 4), 'octaves': octaves,
           'seed': params.get('seed', 0)}
    # the amplitudes as fbm's kernel computes them in float (amp_k = amp_(k-1) * r, each product
    # rounded to float), so that the converted node gives fbm's maps to the bit
    amp = f32(1.0)
    for k in range(octaves):
        out['band_%d' % k] = amp
        amp = f32(amp * f32(r))
    bands.append((id, octaves))
    return out


def pixel_phase(t):
    """t rounded to a multiple of 1/64 (never 0): a shift that is a whole number of pixels at
    every map size from 64 up, so `transform` moves pixels without resampling them."""
    return max(1, round(t * 64)) / 64.0


def finish(g, height, rough, albedo, normal_intensity=0.02, metallic=None, normal_max=None, shift=None, snap=True,
           shift_maps=('alb', 'rgh', 'hgt', 'met')):
    # relief range: up to 10x the default (a free 0..0.1 range turns faint textures into
    # saturated bump noise in random draws and makes the normal map insensitive in fitting)
    if shift:
        # Moves the pattern by (du, dv) texture units so that no tile joint, stripe edge or noise
        # cell border lies on the texture's own border: the wrap-around border must be as smooth
        # as the interior (issue 18's tileability criterion), while joints exactly on it make
        # it a joint line of every map.
        du, dv = (pixel_phase(t) if t and snap else float(t) for t in shift)
        moved = {}
        for key, src in (('alb', albedo), ('rgh', rough), ('hgt', height), ('met', metallic)):
            if src is None or key not in shift_maps:
                moved.setdefault(src, src)
                continue
            if src not in moved:
                moved[src] = g.n('shift_' + key, 'transform', {'in': src}, offset_u=du, offset_v=dv)
        albedo, rough, height = moved[albedo], moved[rough], moved[height]
        metallic = moved.get(metallic) if metallic else None
    # a photograph's pixel-scale grain (surface and sensor), absent from the designed patterns: a
    # white noise finer than any view's pixel, overlaid on the albedo (opacity 0 by default: the
    # identity; a fitting freedom only, not drawn, held in selection's short fits as grain_*)
    g.n('fine', 'white_noise', scale=1024, seed=97)
    g.n('fine_grain', 'blend', {'fg': 'fine', 'bg': albedo}, mode='overlay', opacity=0.0)
    albedo = 'fine_grain'
    if normal_max is None:
        normal_max = round(min(0.1, max(0.02, 10 * normal_intensity)), 4)
    g.n('nrm', 'normal', {'height': height}, intensity=normal_intensity)
    g.p('normal_strength', 'nrm.intensity', doc='relief strength', min=0.0, max=normal_max)
    g.p('grain_fine', 'fine_grain.opacity', min=0.0, max=0.2, draw_spread=0.0,
        doc='pixel-scale albedo grain (overlay opacity of a white noise of 1024 cells a tile)')
    g.out(albedo=albedo, normal='nrm', roughness=rough, height=height)
    if metallic:
        g.out(metallic=metallic)
    g.done()




# ---------------------------------------------------------------- subgraphs shared by many graphs
# (the node list and the parameter list are separate, so a helper may add its parameters before
# or after its nodes without changing either list's order)
def rough_range(g, src, low, high, names=('roughness_min', 'roughness_max'), id='rough', ends=('out_low', 'out_high')):
    """Roughness: `src` remapped by a levels node (0 to `low`, 1 to `high`), out_low and out_high exposed as `names`."""
    g.n(id, 'levels', {'in': src}, out_low=low, out_high=high)
    for name, end in zip(names, ends):
        g.p(name, id + '.' + end)
    return id


def rough_falling(g, src, low, high, names=('roughness_min', 'roughness_max')):
    """rough_range for a roughness falling as `src` rises (low > high): names[0], the minimum, is the node's out_high."""
    return rough_range(g, src, low, high, names, ends=('out_high', 'out_low'))


def colors3(g, id, src, c0, c1, c2, pos=0.5, prefix='color'):
    """A three-colour gradient map of `src`, its dark, mid and light colours exposed."""
    g.n(id, 'gradient_map', {'in': src}, color_0=c0, color_1=c1, color_2=c2, position=pos)
    g.p(prefix + '_dark', id + '.color_0', doc='ramp color at 0')
    g.p(prefix + '_mid', id + '.color_1', doc='ramp color at the midpoint')
    g.p(prefix + '_light', id + '.color_2', doc='ramp color at 1')
    return id


def uniform(g, id, color, param=None):
    """A uniform colour node, its colour exposed as `param` when one is given."""
    g.n(id, 'uniform_color', color=color)
    if param:
        g.p(param, id + '.color')
    return id


def palette(g, colors, names, ids=('ca', 'cb', 'cc')):
    """Uniform colour nodes (ids 'ca', 'cb', ...), each colour exposed under its name."""
    for id, color, name in zip(ids, colors, names):
        uniform(g, id, color, name)
    return ids[:len(colors)]


def blend(g, id, fg, bg, mask=None, param=None, mode=None, opacity=None, **limits):
    """A blend node of `fg` over `bg` (through `mask` if given), its opacity exposed as `param` when given."""
    inputs = {'fg': fg, 'bg': bg}
    if mask:
        inputs['mask'] = mask
    g.n(id, 'blend', inputs, **{k: v for k, v in (('mode', mode), ('opacity', opacity)) if v is not None})
    if param:
        g.p(param, id + '.opacity', **limits)
    return id


def two_tone(g, out, mask, colors, names, ids=('ca', 'cb')):
    """Two exposed uniform colours, the second shown where `mask` is 1: node `out`."""
    palette(g, colors, names, ids)
    return blend(g, out, ids[1], ids[0], mask)


def three_tone(g, colors, names, masks, out=('m1', 'm2')):
    """Three exposed uniform colours: the second over the first through masks[0], the third over that through masks[1]."""
    palette(g, colors, names)
    blend(g, out[0], 'cb', 'ca', masks[0])
    return blend(g, out[1], 'cc', out[0], masks[1])


def warp_weft_colors(g, warp, weft, mask, ids=('ca', 'cb')):
    """Exposed warp and weft colours, the warp shown where `mask` (the weave's warp mask) is 1: node 'cm'."""
    palette(g, (warp, weft), ('warp_color', 'weft_color'), ids)
    return blend(g, 'cm', ids[0], ids[1], mask)


def over_ground(g, fg, id, color, param, mask, out='alb'):
    """`fg` where `mask` is 1, an exposed uniform colour (node `id`) elsewhere (grout, mortar, holes): node `out`."""
    uniform(g, id, color, param)
    return blend(g, out, fg, id, mask)


def shaded(g, color, src, low, param=None, floor=0.0, id='sh', out='alb'):
    """`color` multiplied by `src` remapped to [low, 1]; the darkest shade exposed as `param` (from `floor` to 1)."""
    g.n(id, 'levels', {'in': src}, out_low=low, out_high=1.0)
    if param:
        g.p(param, id + '.out_low', min=floor, max=1.0)
    return blend(g, out, id, color, mode='multiply')


def tinted(g, id, color, color_param, src, low, shade_param=None, floor=0.0, sh='sh', out='alb'):
    """An exposed uniform colour (node `id`) shaded by `src` as in shaded(): node `out`."""
    uniform(g, id, color, color_param)
    return shaded(g, id, src, low, shade_param, floor, sh, out)


def fuzz(g, src, scale, opacity, seed, id='hf'):
    """`src` overlaid with fine fbm fuzz (node 'fz'), its opacity exposed as `fuzz`: node `id`."""
    g.n('fz', 'fbm', scale_x=scale, scale_y=scale, octaves=2, roughness=0.5, seed=seed)
    return blend(g, id, 'fz', src, param='fuzz', mode='overlay', opacity=opacity)


def diagonals(g, ids, count, width, softness):
    """Two stripe nodes alike but for their direction: one diagonal, one antidiagonal."""
    for id, direction in zip(ids, ('diagonal', 'antidiagonal')):
        g.n(id, 'stripes', count=count, direction=direction, width=width, softness=softness)


def triangle_waves(g, repeats):
    """Triangle waves along u ('tu') and v ('tv'); blended they give diamonds or squares."""
    for id, direction in (('tu', 'u'), ('tv', 'v')):
        g.n(id, 'gradient_linear', direction=direction, repeats=repeats, shape='triangle')


def staggered_discs(g, ids, count, size, softness, offset):
    """A grid of discs and its copy moved by `offset` along u and v, merged (max): node ids[2]."""
    g.n(ids[0], 'shape', count=count, shape='disc', size=size, softness=softness)
    g.n(ids[1], 'transform', {'in': ids[0]}, offset_u=offset, offset_v=offset)
    return blend(g, ids[2], ids[0], ids[1], mode='max')


def fully_metallic(g):
    """A metallic map of 1 everywhere (node 'metal'), exposed as `metallic`."""
    g.n('metal', 'uniform_gray', value=1.0)
    g.p('metallic', 'metal.value')
    return 'metal'


def metallic_where(g, mask, high, param):
    """A metallic map following `mask` (0 to `high`), its high end exposed as `param`: node 'metal'."""
    g.n('metal', 'levels', {'in': mask}, out_low=0.0, out_high=high)
    g.p(param, 'metal.out_high')
    return 'metal'


# ---------------------------------------------------------------- wood
def wood_grain(g, seed=1, rings=36, warp=0.025, fiber=0.35):
    """Gray grain along u: soft stripes across v, gently wavy (long waves), with fine fibers."""
    g.n('ring', 'stripes', count=rings, direction='v', width=0.35, softness=0.35)
    return wavy_fibers(g, 'ring', seed, 1, warp, fiber)


def wavy_fibers(g, rings, seed, wave_scale, warp, fiber):
    """The rings `rings` (from stripe node 'ring') bent by long fbm waves, overlaid with fine fibers: node 'grain'."""
    g.n('wave', 'fbm', scale_x=wave_scale, scale_y=2, octaves=3, roughness=0.35, seed=seed)
    g.n('wavy', 'directional_warp', {'in': rings, 'height': 'wave'}, intensity=warp, angle=0.25)
    g.p('ring_waviness', 'wavy.intensity', min=0.0, max=0.05)
    g.p('ring_width', 'ring.width', min=0.1, max=0.8)
    g.n('fib', 'fbm', scale_x=4, scale_y=96, octaves=3, roughness=0.6, seed=seed + 7)
    return blend(g, 'grain', 'fib', 'wavy', param='fiber_strength', mode='overlay', opacity=fiber, min=0.0, max=1.0)


def wood_colors(g, src, light=(0.45, 0.26, 0.12), mid=(0.30, 0.15, 0.06), dark=(0.16, 0.07, 0.025)):
    """The wood colour ramp (node 'wcol') over the gray grain `src`."""
    return colors3(g, 'wcol', src, list(dark), list(mid), list(light), 0.5, 'wood')


def dark_joints(g, base, height, color, out='alb', out_first=False, **params):
    """`base` multiplied by a dark uniform colour in the joints (where the tile `height` is low): node `out`."""
    if out_first:
        blend(g, out, 'gapc', base, 'gapm', mode='multiply', **params)
    g.n('gapm', 'invert', {'in': height})
    g.n('gapc', 'uniform_color', color=color)
    if not out_first:
        blend(g, out, 'gapc', base, 'gapm', mode='multiply', **params)
    return out


def finish_wood(g, grain, joints, albedo, rough, shift, **kw):
    """Finishes a floor of wood pieces: the grain faintly in the joints' relief, the roughness following the grain."""
    g.n('h', 'blend', {'fg': grain, 'bg': joints}, mode='multiply', opacity=0.15)
    finish(g, 'h', rough_range(g, grain, *rough), albedo, 0.005, normal_max=0.03, shift=shift, **kw)


def grain_scale(g, tiles):
    """Exposes the tile node `tiles`' pattern_scale as `grain_scale`: a grain finer or coarser than the planks,
    so that a fit sets the plank size and the grain's apart. A fitting freedom only: not drawn (draw_spread 0
    takes no random stream, so every other parameter's draw, and the exemplar bank, stay as they were).
    Its name starts with grain_, so selection's short fits hold it (SynthesisOptions::heldParameters) and
    the part's fit moves it."""
    g.p('grain_scale', tiles + '.pattern_scale', min=0.35, max=2.0, draw_spread=0.0,
        doc="grain cycles per plank relative to the grain node's (the planks unchanged)")


def wood_planks(name, desc, grain_fn, rows, cols, layout, col, seed, tint=0.5, lum_var=0.5, gap=0.02, bevel=0.03,
                rough=(0.5, 0.38), shift=None, first=False):
    """Planks cut from the grain `grain_fn(g, seed)`; `first`: the library's first plank floors (rows and row
    offset exposed, the joint node 'gap_dark' listed ahead of its inputs), kept so that their files stay as they are."""
    g = G(name, 'wood', desc)
    grain = grain_fn(g, seed)
    g.n('tiles', 'tile', {'pattern': grain}, layout=layout, rows=rows, cols=cols, row_offset=0.5 if layout == 'bricks' else 0.9,
        gap=gap, bevel=bevel, lum_var=lum_var, seed=seed)
    g.p('plank_gap', 'tiles.gap', min=0.0, max=0.1)
    g.p('plank_bevel', 'tiles.bevel', min=0.005, max=0.2)
    if first:
        g.p('plank_rows', 'tiles.rows', min=2, max=24)
        g.p('row_offset', 'tiles.row_offset')
    g.p('plank_variation', 'tiles.lum_var')
    if not first:
        # not on the first floors: at the default (1) every sample sits on a pixel centre, where the
        # map's derivative in the scale has a kink (the colour ramp's clamp meets a grain of exactly
        # 0 or 1), and their random draws put a finite-difference check there; they stay as they were
        grain_scale(g, 'tiles')
    c = wood_colors(g, 'tiles.sampled', *col)
    blend(g, 'tint', 'tiles.random', c, param='plank_tint', mode='overlay', opacity=tint, doc='per-plank brightness variation')
    alb = dark_joints(g, 'tint', 'tiles.height', [0.25, 0.2, 0.17], 'gap_dark' if first else 'alb', first, opacity=1.0)
    # the roughness follows the unsampled grain (no joints): only albedo and height move. Shift: by
    # default half a plank; the random row offsets of `planks` can still put a plank end on the
    # border, then a measured shift is given (the first floors move along v only: a plank end lies
    # on the border no more often than on any other column, and moving them along u also made the
    # optim test's UV-rotation recovery on wood_planks land 34 degrees off)
    finish_wood(g, grain, 'tiles.height', alb, rough, shift or ((0.25 if layout == 'bricks' else 0.5) / cols, 0.5 / rows),
                shift_maps=('alb', 'hgt'))


wood_planks('wood_planks', 'Oak-like floor planks with random row offsets, grain following each plank.', wood_grain, 8, 2, 'planks',
            ((0.50, 0.30, 0.14), (0.34, 0.18, 0.07), (0.18, 0.08, 0.03)), 1, shift=(0.0, 0.5 / 8), first=True)
wood_planks('wood_planks_dark', 'Dark walnut-like wide planks.', wood_grain, 6, 1, 'planks',
            ((0.20, 0.10, 0.05), (0.12, 0.06, 0.03), (0.06, 0.03, 0.015)), 5, shift=(0.0, 0.5 / 6), first=True)
wood_planks('wood_planks_light', 'Light maple/pine planks in a regular running bond.', wood_grain, 10, 3, 'bricks',
            ((0.70, 0.52, 0.32), (0.58, 0.40, 0.22), (0.40, 0.26, 0.12)), 9, first=True)


def parquet_herringbone():
    g = G('wood_parquet_herringbone', 'wood', 'Herringbone parquet; the grain turns with every plank.')
    grain = wood_grain(g, rings=48, seed=3, warp=0.015)
    g.n('hb', 'herringbone', {'pattern': grain}, count=2, ratio=4, gap=0.04, bevel=0.06, lum_var=0.6, seed=4)
    g.p('plank_ratio', 'hb.ratio')
    g.p('repeats', 'hb.count', min=1, max=6)
    g.p('plank_gap', 'hb.gap', min=0.0, max=0.2)
    g.p('plank_bevel', 'hb.bevel', min=0.005, max=0.3)
    c = wood_colors(g, 'hb.sampled', (0.52, 0.32, 0.15), (0.36, 0.19, 0.08), (0.2, 0.09, 0.035))
    blend(g, 'tint', 'hb.random', c, param='plank_tint', mode='overlay', opacity=0.5)
    dark_joints(g, 'tint', 'hb.height', [0.3, 0.25, 0.2])
    finish_wood(g, grain, 'hb.height', 'alb', (0.45, 0.35), (1 / 64, 3 / 64))


parquet_herringbone()


def parquet_grid():
    g = G('wood_parquet_checker', 'wood', 'Basket parquet: square blocks alternating the grain direction.')
    grain = wood_grain(g, rings=64, seed=11, warp=0.012)
    g.n('rot', 'transform', {'in': grain}, rotation='90')
    g.n('chk', 'checker', count=3, softness=0.005)  # 3 periods of 2 x 2 squares: one per block
    g.n('mix', 'blend', {'fg': 'rot', 'bg': grain, 'mask': 'chk'})
    g.n('tiles', 'tile', {'pattern': 'mix'}, layout='grid', rows=6, cols=6, gap=0.02, bevel=0.04, lum_var=0.5, seed=12)
    g.p('block_gap', 'tiles.gap', min=0.0, max=0.1)
    g.p('block_bevel', 'tiles.bevel', min=0.005, max=0.2)
    g.p('block_variation', 'tiles.lum_var')
    c = wood_colors(g, 'mix', (0.55, 0.36, 0.18), (0.40, 0.23, 0.10), (0.22, 0.11, 0.04))
    blend(g, 'tint', 'tiles.random', c, param='block_tint', mode='overlay', opacity=0.4)
    finish_wood(g, grain, 'tiles.height', 'tint', (0.45, 0.35), (1 / 12, 1 / 12))


parquet_grid()


def veneer():
    g = G('wood_veneer', 'wood', 'Continuous wood veneer (furniture, doors): flowing grain, satin finish.')
    grain = wood_grain(g, rings=20, seed=21, warp=0.04, fiber=0.3)
    c = wood_colors(g, grain, (0.62, 0.40, 0.20), (0.46, 0.26, 0.11), (0.28, 0.13, 0.05))
    g.n('hsl', 'hsl', {'in': c})
    g.p('hue_shift', 'hsl.hue', min=-0.01, max=0.01)
    g.p('saturation', 'hsl.saturation', min=0.85, max=1.2)
    r = rough_range(g, grain, 0.35, 0.25)
    g.n('h', 'levels', {'in': grain}, out_low=0.4, out_high=0.6)
    finish(g, 'h', r, 'hsl', 0.005)


veneer()


def painted_wood():
    g = G('wood_painted', 'wood', 'Painted wooden boards: paint color over faint grain and plank seams.')
    grain = wood_grain(g, rings=30, seed=31, warp=0.025, fiber=0.5)
    g.n('tiles', 'tile', {'pattern': grain}, layout='bricks', rows=2, cols=6, gap=0.005, bevel=0.01, lum_var=0.1, seed=32)
    g.p('board_count', 'tiles.cols', min=2, max=16)
    g.p('board_gap', 'tiles.gap', min=0.0, max=0.05)
    grain_scale(g, 'tiles')
    g.n('rot', 'transform', {'in': 'tiles.sampled'}, rotation='90')
    tinted(g, 'paint', [0.70, 0.69, 0.64], 'paint_color', 'rot', 0.85, 'grain_show_through', 0.5, sh='shade', out='alb0')
    # the board layout turns with the grain (horizontal boards, grain along them)
    g.n('roth', 'transform', {'in': 'tiles.height'}, rotation='90')
    g.n('gapm', 'invert', {'in': 'roth'})
    g.n('alb', 'blend', {'fg': 'gapm', 'bg': 'alb0'}, mode='subtract', opacity=0.5)
    g.n('h', 'blend', {'fg': 'rot', 'bg': 'roth'}, mode='multiply', opacity=0.1)
    r = rough_range(g, 'rot', 0.45, 0.3)
    g.n('rj', 'blend', {'fg': 'gapm', 'bg': r}, mode='add', opacity=0.3)
    finish(g, 'h', 'rj', 'alb', 0.005, normal_max=0.03, shift=(0.25, 1 / 24))


painted_wood()

# ---------------------------------------------------------------- tiles
def joint_params(g, id, grout=(0.0, 0.3), bevel=(0.005, 0.3)):
    """A tile node's grout width, bevel (unless `bevel` is None) and tile variation exposed."""
    g.p('grout_width', id + '.gap', min=grout[0], max=grout[1])
    if bevel:
        g.p('bevel', id + '.bevel', min=bevel[0], max=bevel[1])
    g.p('tile_variation', id + '.lum_var')


def mottled(g, random, scale, opacity, octaves=5, seed=5, cloud='cloud', param='surface_mottling'):
    """Per-tile values `random` overlaid with an fbm cloud (node `cloud`), its opacity exposed as `param`: node 'var'."""
    g.n(cloud, 'fbm', scale_x=scale, scale_y=scale, octaves=octaves, roughness=0.5, seed=seed)
    return blend(g, 'var', cloud, random, param=param, mode='overlay', opacity=opacity)


def grout_rough(g, joints, tile_rough, tile='tile'):
    """Roughness from the tile mask `joints`: matte grout (0.8), `tile_rough` on the faces, both exposed."""
    return rough_range(g, joints, 0.8, tile_rough, ('roughness_grout', 'roughness_' + tile))


def glazed_in_grout(g, grout, tile_rough, shift):
    """Finishes glazed tiles (colour node 'tc', tile node 't'): exposed grout colour in the joints, faint fbm
    relief, glossy faces in matte grout."""
    over_ground(g, 'tc', 'gc', grout, 'grout_color', 't.height')
    g.n('gn', 'fbm', scale_x=32, scale_y=32, octaves=3, roughness=0.5, seed=9)
    g.n('h', 'blend', {'fg': 'gn', 'bg': 't.height'}, mode='multiply', opacity=0.05)
    g.n('rm', 'blend', {'fg': 't.height', 'bg': 'gn'}, mode='copy', opacity=0.9)
    grout_rough(g, 'rm', tile_rough)
    finish(g, 'h', 'rough', 'alb', 0.01, shift=shift)


def tile_graph(name, desc, layout, rows, cols, tile_col, grout_col, gap, bevel, var, rough=(0.12, 0.2), noise_scale=4,
               category='tile'):
    g = G(name, category, desc)
    g.n('t', 'tile', layout=layout, rows=rows, cols=cols, row_offset=0.5, gap=gap, bevel=bevel, lum_var=var, seed=3)
    g.p('rows', 't.rows', min=max(1, rows // 3), max=rows * 3)
    g.p('cols', 't.cols', min=max(1, cols // 3), max=cols * 3)
    joint_params(g, 't')
    mottled(g, 't.random', noise_scale, 0.3)
    g.n('tc', 'gradient_map', {'in': 'var'}, color_0=[c * 0.8 for c in tile_col], color_1=tile_col,
        color_2=[min(1.0, c * 1.15) for c in tile_col], position=0.5)
    g.p('tile_color', 'tc.color_1')
    g.p('tile_color_dark', 'tc.color_0')
    glazed_in_grout(g, grout_col, rough[0], ((0.25 if layout == 'bricks' else 0.5) / cols, 0.5 / rows))


tile_graph('tile_square_ceramic', 'Square glazed ceramic tiles with light grout.', 'grid', 6, 6,
           [0.78, 0.78, 0.76], [0.55, 0.53, 0.5], 0.05, 0.05, 0.15)
tile_graph('tile_subway', 'White subway tiles (2:1) in running bond with grey grout.', 'bricks', 16, 8,
           [0.85, 0.86, 0.85], [0.35, 0.35, 0.35], 0.08, 0.15, 0.1)
tile_graph('tile_large_porcelain', 'Large-format matte porcelain floor tiles, thin grout.', 'grid', 2, 2,
           [0.55, 0.53, 0.5], [0.35, 0.34, 0.32], 0.015, 0.02, 0.2, rough=(0.5, 0.6))
tile_graph('tile_terracotta', 'Terracotta floor tiles, warm and uneven.', 'grid', 4, 4,
           [0.55, 0.22, 0.1], [0.45, 0.42, 0.38], 0.07, 0.08, 0.6, rough=(0.6, 0.7))
tile_graph('tile_mosaic', 'Small square glass mosaic with varied blue-green tiles.', 'grid', 24, 24,
           [0.18, 0.42, 0.5], [0.7, 0.7, 0.68], 0.12, 0.12, 0.8, rough=(0.08, 0.15), noise_scale=2)
# issue 18: narrow glazed strips in rows that do not line up (polyhaven floor_long_white_tiles, the
# blender-room example's floor): 5 rows of 16 per tile, about 1:3.2, each row shifted at random
tile_graph('tile_stack_narrow', 'Narrow glazed porcelain strips (about 1:3) in rows shifted at random, '
           'cream with beige grout.', 'planks', 5, 16, [0.86, 0.84, 0.78], [0.6, 0.54, 0.42], 0.04, 0.03, 0.1,
           rough=(0.2, 0.3))


def checker_tiles():
    g = G('tile_checker', 'tile', 'Black and white checker floor tiles (two colours alternating, thin grout).')
    g.n('t', 'tile', layout='grid', rows=8, cols=8, row_offset=0.0, gap=0.03, bevel=0.04, lum_var=0.05, seed=3)
    # the checker node's count is periods of 2 x 2 squares: count 4 gives the 8 x 8 squares of
    # the 8 x 8 tiles (one colour per tile)
    g.n('chk', 'checker', count=4, softness=0.002)
    joint_params(g, 't', grout=(0.0, 0.2))
    mottled(g, 't.random', 4, 0.2)
    g.n('ca', 'gradient_map', {'in': 'var'}, color_0=[0.62, 0.62, 0.6], color_1=[0.75, 0.75, 0.73], color_2=[0.82, 0.82, 0.8])
    g.p('light_tile_color', 'ca.color_1')
    g.n('cb', 'gradient_map', {'in': 'var'}, color_0=[0.012, 0.012, 0.013], color_1=[0.025, 0.025, 0.027], color_2=[0.04, 0.04, 0.042])
    g.p('dark_tile_color', 'cb.color_1')
    blend(g, 'tc', 'ca', 'cb', 'chk')
    glazed_in_grout(g, [0.45, 0.44, 0.42], 0.12, (1 / 16, 1 / 16))


checker_tiles()


def hex_tiles():
    g = G('tile_hexagon', 'tile', 'Hexagon-like penny mosaic: discs of glazed tile in grout (offset rows).')
    staggered_discs(g, ('d1', 'd2', 'd'), 12, 0.9, 0.06, 0.0416667)
    g.p('tile_size', 'd1.size', min=0.5, max=1.0)
    g.p('edge_softness', 'd1.softness', min=0.02, max=0.2)
    g.n('rnd', 'white_noise', scale=24, seed=4)
    g.n('tc', 'gradient_map', {'in': 'rnd'}, color_0=[0.75, 0.75, 0.72], color_1=[0.8, 0.8, 0.78], color_2=[0.9, 0.9, 0.88])
    g.p('tile_color_a', 'tc.color_0')
    g.p('tile_color_b', 'tc.color_2')
    over_ground(g, 'tc', 'gc', [0.3, 0.3, 0.3], 'grout_color', 'd')
    grout_rough(g, 'd', 0.1)
    finish(g, 'd', 'rough', 'alb', 0.004, shift=(1 / 64, 1 / 64))


hex_tiles()

# ---------------------------------------------------------------- stone
def marble(name, desc, base, vein, seed, scale=2):
    g = G(name, 'stone', desc)
    g.n('f', 'fbm', scale_x=scale, scale_y=scale, octaves=6, roughness=0.55, seed=seed)
    g.n('w', 'fbm', scale_x=scale, scale_y=scale, octaves=5, roughness=0.5, seed=seed + 1)
    g.n('s', 'stripes', count=3, direction='diagonal', width=0.08, softness=0.15)
    g.n('sw', 'warp', {'in': 's', 'height': 'w'}, intensity=0.004)
    g.n('sw2', 'directional_warp', {'in': 'sw', 'height': 'f'}, intensity=0.15, angle=0.1)
    g.p('vein_width', 's.width', min=0.01, max=0.3)
    g.p('vein_turbulence', 'sw.intensity', min=0.0, max=0.01)
    g.p('vein_flow', 'sw2.intensity', min=0.0, max=0.2)
    g.n('veins', 'levels', {'in': 'sw2'}, gamma=0.6)
    g.p('vein_contrast', 'veins.gamma', min=0.2, max=1.5)
    blend(g, 'cl', 'f', 'veins', param='clouding', mode='screen', opacity=0.3)
    g.n('col', 'gradient_map', {'in': 'cl'}, color_0=base, color_1=[(a + b) / 2 for a, b in zip(base, vein)], color_2=vein, position=0.6)
    g.p('stone_color', 'col.color_0')
    g.p('vein_color', 'col.color_2')
    rough_range(g, 'veins', 0.08, 0.15, ('roughness_base', 'roughness_veins'))
    finish(g, 'veins', 'rough', 'col', 0.001)


marble('stone_marble_white', 'White Carrara-like polished marble with grey veins.', [0.82, 0.82, 0.8], [0.35, 0.36, 0.38], 41)
marble('stone_marble_dark', 'Dark polished marble (Nero Marquina-like) with white veins.', [0.04, 0.04, 0.045], [0.75, 0.75, 0.73], 43)


def marble_veined():
    # issue 18: the photographed dark marbles (ambientcg marble006 / 016) hold a network of fine
    # veins, where marble() draws a few broad warped stripes. A vein runs along the mid-level
    # contour of a noise field: a tent curve peaks where the field crosses 0.5 and a levels
    # threshold keeps the ridge's top; a coarse net and a fine one, drawn out along one
    # direction, over a clouded and speckled ground. Screen blends keep it differentiable (a
    # max kinks where the layers tie).
    g = G('stone_marble_veined', 'stone', 'Marble with a network of fine veins (Nero Marquina, '
          'Calacatta, grey Bardiglio): veins along the mid-level contour of two warped noise '
          'fields, a coarse net and a fine one, over a clouded ground.')
    g.n('flow', 'fbm', scale_x=2, scale_y=2, octaves=4, roughness=0.5, seed=61)
    for net, scale, octaves, rough, seed, flow, low, high in (('1', 3, 5, 0.45, 62, 0.08, 0.85, None),
                                                              ('2', 6, 4, 0.5, 63, 0.05, 0.9, 0.5)):
        g.n('n' + net, 'fbm', scale_x=scale, scale_y=scale, octaves=octaves, roughness=rough, seed=seed)
        g.n('n%sw' % net, 'directional_warp', {'in': 'n' + net, 'height': 'flow'}, intensity=flow, angle=0.12)
        g.n('t' + net, 'curve', {'in': 'n%sw' % net}, p0=0, p1=0, p2=1, p3=0, p4=0)
        levels = dict(in_low=low, gamma=0.7)
        if high is not None:
            levels['out_high'] = high
        g.n('v' + net, 'levels', {'in': 't' + net}, **levels)
    blend(g, 'veins', 'v2', 'v1', mode='screen', opacity=1)
    g.n('cloud', 'fbm', scale_x=2, scale_y=2, octaves=6, roughness=0.6, seed=64)
    g.n('grain', 'fbm', scale_x=48, scale_y=48, octaves=2, roughness=0.5, seed=65)
    blend(g, 'cg', 'grain', 'cloud', mode='overlay', opacity=0.3)
    g.n('ground', 'levels', {'in': 'cg'}, out_low=0.0, out_high=0.3)
    blend(g, 'mix', 'veins', 'ground', mode='screen', opacity=1)
    g.n('col', 'gradient_map', {'in': 'mix'}, color_0=[0.03, 0.03, 0.035], color_1=[0.12, 0.12, 0.125],
        color_2=[0.7, 0.7, 0.68], position=0.3)
    g.p('vein_width', 'v1.in_low', min=0.6, max=0.98, doc="main veins' threshold on the contour ridge (lower: wider veins)")
    g.p('fine_vein_width', 'v2.in_low', min=0.6, max=0.98, doc="fine veins' threshold (lower: wider)")
    g.p('fine_vein_strength', 'v2.out_high', min=0.0, max=1.0, doc='how bright the fine net is against the main veins')
    g.p('vein_sharpness', 'v1.gamma', 'v2.gamma', min=0.2, max=2.0, doc='profile across a vein (low: thin bright core)')
    g.p('vein_flow', 'n1w.intensity', 'n2w.intensity', min=0.0, max=0.2, doc='how far the veins are drawn out along one direction')
    g.p('flow_angle', 'n1w.angle', 'n2w.angle', min=-0.5, max=0.5, doc='direction the veins are drawn out along (turns)')
    g.p('clouding', 'ground.out_high', min=0.0, max=1.0, doc='variation of the ground between the veins')
    g.p('grain', 'cg.opacity', min=0.0, max=1.0, doc='fine speckle of the ground')
    g.p('ground_color', 'col.color_0')
    g.p('cloud_color', 'col.color_1')
    g.p('vein_color', 'col.color_2')
    rough_range(g, 'veins', 0.1, 0.2, ('roughness_base', 'roughness_veins'))
    finish(g, 'veins', 'rough', 'col', 0.001)


marble_veined()


def granite(name, desc, c0, c1, c2, seed, cat='stone', rough=(0.15, 0.3), scale=64):
    g = G(name, cat, desc)
    g.n('v', 'voronoi', scale=scale, jitter=1.0, mode='cell_value', seed=seed)
    g.n('f', 'fbm', scale_x=8, scale_y=8, octaves=5, roughness=0.6, seed=seed + 1)
    blend(g, 'm', 'f', 'v', param='cloudiness', mode='overlay', opacity=0.5)
    g.n('hs', 'histogram_scan', {'in': 'm'}, position=0.5, contrast=0.3)
    g.p('speckle_amount', 'hs.position', min=0.2, max=0.8)
    g.p('speckle_contrast', 'hs.contrast', min=0.0, max=0.9)
    colors3(g, 'col', 'hs', c0, c1, c2, 0.5, 'stone')
    rough_range(g, 'hs', *rough)
    g.n('h', 'levels', {'in': 'f'}, out_low=0.45, out_high=0.55)
    finish(g, 'h', 'rough', 'col', 0.005)


granite('stone_granite', 'Speckled granite countertop, polished.', [0.08, 0.08, 0.08], [0.45, 0.42, 0.4], [0.8, 0.78, 0.75], 51)
granite('stone_granite_red', 'Red-brown speckled granite.', [0.1, 0.05, 0.04], [0.45, 0.22, 0.16], [0.7, 0.6, 0.55], 53)


def terrazzo():
    g = G('stone_terrazzo', 'stone', 'Terrazzo: stone chips of several colors in a light cement matrix.')
    g.n('v', 'voronoi', scale=20, jitter=1.0, mode='f2_minus_f1', seed=61)
    g.n('chips', 'histogram_scan', {'in': 'v'}, position=0.45, contrast=0.85)
    g.p('chip_density', 'chips.position', min=0.2, max=0.8)
    g.n('cv', 'voronoi', scale=20, jitter=1.0, mode='cell_value', seed=61)
    g.n('cc', 'gradient_map', {'in': 'cv'}, color_0=[0.15, 0.15, 0.15], color_1=[0.55, 0.3, 0.2], color_2=[0.7, 0.7, 0.68], position=0.5)
    for i, letter in enumerate('abc'):
        g.p('chip_color_' + letter, 'cc.color_%d' % i)
    g.n('f', 'fbm', scale_x=16, scale_y=16, octaves=4, roughness=0.5, seed=62)
    g.n('mc', 'gradient_map', {'in': 'f'}, color_0=[0.72, 0.7, 0.66], color_1=[0.78, 0.76, 0.72], color_2=[0.84, 0.82, 0.78])
    g.p('matrix_color', 'mc.color_1')
    blend(g, 'alb', 'cc', 'mc', 'chips')
    rough_range(g, 'chips', 0.3, 0.2, ('roughness_matrix', 'roughness_chips'))
    g.n('h', 'levels', {'in': 'f'}, out_low=0.48, out_high=0.52)
    finish(g, 'h', 'rough', 'alb', 0.005)


terrazzo()


def travertine():
    g = G('stone_travertine', 'stone', 'Travertine tiles: banded beige stone with small pits.')
    g.n('band', 'fbm', scale_x=1, scale_y=12, octaves=5, roughness=0.55, seed=71)
    g.n('pits', 'voronoi', scale=48, jitter=1.0, mode='f1', seed=72)
    g.n('pitm', 'histogram_scan', {'in': 'pits'}, position=0.9, contrast=0.8)
    g.p('pit_amount', 'pitm.position', min=0.8, max=1.0)
    g.n('t', 'tile', {'pattern': 'band'}, layout='bricks', rows=4, cols=2, gap=0.02, bevel=0.02, lum_var=0.3, seed=73)
    g.p('tile_rows', 't.rows', min=2, max=8)
    g.p('grout_width', 't.gap', min=0.0, max=0.1)
    colors3(g, 'col', 't.sampled', [0.55, 0.45, 0.33], [0.7, 0.6, 0.47], [0.82, 0.75, 0.63], 0.5, 'stone')
    uniform(g, 'pc', [0.45, 0.37, 0.27])
    blend(g, 'alb0', 'pc', 'col', 'pitm', opacity=0.7)
    blend(g, 'alb', 't.random', 'alb0', mode='overlay', opacity=0.2)
    g.n('h0', 'blend', {'fg': 'pitm', 'bg': 't.height'}, mode='subtract', opacity=0.5)
    rough_range(g, 'band', 0.45, 0.6)
    finish(g, 'h0', 'rough', 'alb', 0.005, shift=(0.125, 0.125))


travertine()


def slate():
    g = G('stone_slate', 'stone', 'Cleft slate flagstones: dark grey layered stone in a grid.')
    g.n('f', 'fbm', scale_x=4, scale_y=4, octaves=7, roughness=0.6, seed=81)
    g.n('t', 'tile', {'pattern': 'f'}, layout='bricks', rows=3, cols=2, gap=0.03, bevel=0.05, lum_var=0.5, seed=82)
    g.p('rows', 't.rows', min=2, max=8)
    g.p('gap', 't.gap', min=0.0, max=0.1)
    g.p('variation', 't.lum_var')
    blend(g, 'cl', 't.random', 't.sampled', mode='overlay', opacity=0.5)
    colors3(g, 'col', 'cl', [0.06, 0.065, 0.07], [0.16, 0.17, 0.18], [0.3, 0.3, 0.3])
    uniform(g, 'gc', [0.25, 0.24, 0.23])
    blend(g, 'alb', 'col', 'gc', 't.height')
    g.n('h', 'blend', {'fg': 't.sampled', 'bg': 't.height'}, mode='multiply', opacity=0.6)
    # roughness: the flag's own (shifted) cleft pattern on the stone, the grout's value in the
    # joints; every flag samples the pattern at another offset, so the mask keeps the change of
    # pattern inside the joint instead of a roughness step along every flag border
    rough_range(g, 't.sampled', 0.5, 0.8, id='rs')
    g.n('rg', 'uniform_gray', value=0.9)
    g.p('roughness_grout', 'rg.value')
    blend(g, 'rough', 'rs', 'rg', 't.height')
    finish(g, 'h', 'rough', 'alb', 0.01, shift=(0.125, 0.125))


slate()

# ---------------------------------------------------------------- concrete / plaster / paint
def pitted(g, base, scale, seed, position, floor, out):
    """`base` with pores (the centres of voronoi cells, node 'pm', exposed as pore_amount) subtracted: node `out`."""
    g.n('p', 'voronoi', scale=scale, jitter=1.0, mode='f1', seed=seed)
    g.n('pm', 'histogram_scan', {'in': 'p'}, position=position, contrast=0.7)
    g.p('pore_amount', 'pm.position', min=floor, max=1.0)
    return blend(g, out, 'pm', base, mode='subtract', opacity=0.5)


def cementish(name, cat, desc, c, scale, pores, rough, relief, seed):
    g = G(name, cat, desc)
    g.n('f', 'fbm', scale_x=scale, scale_y=scale, octaves=7, roughness=0.6, seed=seed)
    g.n('big', 'fbm', scale_x=2, scale_y=2, octaves=3, roughness=0.5, seed=seed + 1)
    blend(g, 'm', 'big', 'f', param='stain_amount', mode='overlay', opacity=0.6)
    pitted(g, 'm', pores, seed + 2, 0.93, 0.85, 'mm')
    g.n('col', 'gradient_map', {'in': 'mm'}, color_0=[x * 0.7 for x in c], color_1=c, color_2=[min(1, x * 1.2) for x in c])
    g.p('base_color', 'col.color_1')
    g.p('dark_color', 'col.color_0')
    g.p('light_color', 'col.color_2')
    finish(g, 'mm', rough_range(g, 'f', *rough), 'col', relief)


cementish('concrete_smooth', 'concrete', 'Smooth poured concrete with cloudy stains and small pores.', [0.5, 0.49, 0.47], 6, 40, (0.7, 0.85), 0.004, 91)
cementish('concrete_rough', 'concrete', 'Rough board-formed concrete, darker, with many pores.', [0.38, 0.37, 0.36], 12, 60, (0.8, 0.95), 0.01, 93)
cementish('concrete_polished', 'concrete', 'Polished concrete floor, low roughness.', [0.55, 0.54, 0.52], 4, 30, (0.25, 0.4), 0.002, 95)
cementish('plaster_smooth', 'plaster', 'Smooth white plaster wall with faint trowel clouding.', [0.8, 0.79, 0.76], 3, 80, (0.75, 0.85), 0.002, 101)
cementish('plaster_stucco', 'plaster', 'Sprayed stucco / orange-peel wall texture.', [0.76, 0.73, 0.68], 24, 64, (0.8, 0.9), 0.02, 103)


def venetian():
    g = G('plaster_venetian', 'plaster', 'Venetian plaster: polished, cloudy, layered trowel strokes.')
    g.n('f', 'fbm', scale_x=3, scale_y=2, octaves=6, roughness=0.6, seed=111)
    g.n('st', 'directional_blur', {'in': 'f'}, length=0.08, angle=0.08, taps=12)
    g.p('stroke_length', 'st.length', min=0.0, max=0.2)
    g.p('stroke_angle', 'st.angle')
    g.n('lv', 'levels', {'in': 'st'}, in_low=0.2, in_high=0.8)
    colors3(g, 'col', 'lv', [0.6, 0.53, 0.44], [0.69, 0.62, 0.52], [0.77, 0.71, 0.61])
    finish(g, 'lv', rough_range(g, 'lv', 0.2, 0.35), 'col', 0.001)


venetian()


def tinted_fbm(name, category, desc, col, color_param, shade, scale, rough, relief, seed):
    """A uniform colour faintly shaded by fbm, the fbm also in roughness and relief (paints, plastics)."""
    g = G(name, category, desc)
    g.n('f', 'fbm', scale_x=scale, scale_y=scale, octaves=4, roughness=0.5, seed=seed)
    tinted(g, 'c', col, color_param, 'f', shade, 'color_variation', 0.8)
    finish(g, 'f', rough_range(g, 'f', *rough), 'alb', relief)


for name, desc, col, scale, rough, relief, seed in [
        ('paint_matte_wall', 'Matte painted wall (roller texture).', [0.75, 0.73, 0.68], 48, (0.8, 0.9), 0.004, 121),
        ('paint_eggshell', 'Eggshell paint, slight sheen, colored.', [0.45, 0.55, 0.62], 64, (0.4, 0.5), 0.002, 123),
        ('paint_glossy', 'Glossy enamel paint (doors, trim).', [0.9, 0.9, 0.88], 8, (0.08, 0.12), 0.001, 125)]:
    tinted_fbm(name, 'paint', desc, col, 'paint_color', 0.96, scale, rough, relief, seed)


def textured_wall():
    g = G('paint_textured_wall', 'paint', 'Painted textured wall (knock-down): flattened blobs.')
    g.n('v', 'voronoi', scale=16, jitter=1.0, mode='f1', seed=131)
    g.n('f', 'fbm', scale_x=16, scale_y=16, octaves=4, roughness=0.5, seed=132)
    g.n('m', 'blend', {'fg': 'f', 'bg': 'v'}, mode='add', opacity=0.6)
    g.n('hs', 'histogram_scan', {'in': 'm'}, position=0.45, contrast=0.6)
    g.p('blob_coverage', 'hs.position', min=0.2, max=0.8)
    g.p('blob_sharpness', 'hs.contrast', min=0.0, max=0.9)
    tinted(g, 'c', [0.8, 0.77, 0.7], 'paint_color', 'hs', 0.92, 'shade', 0.7)
    rough_range(g, 'hs', 0.85, 0.7, ('roughness_low', 'roughness_high'))
    finish(g, 'hs', 'rough', 'alb', 0.004)


textured_wall()

# ---------------------------------------------------------------- wallpaper
def paper_texture(g, base, seed, opacity, param='paper_texture'):
    """Fine paper fbm (node 'paper') overlaid on `base`, its opacity exposed as `param` when given: node 'alb'."""
    g.n('paper', 'fbm', scale_x=64, scale_y=64, octaves=3, roughness=0.5, seed=seed)
    return blend(g, 'alb', 'paper', base, param=param, mode='overlay', opacity=opacity)


def wallpaper_stripes():
    g = G('wallpaper_stripes', 'wallpaper', 'Striped wallpaper: two-tone vertical stripes with a pinstripe, paper texture.')
    for id, width in (('s', 0.5), ('pin', 0.04)):
        g.n(id, 'stripes', count=8, direction='u', width=width, softness=0.01)
    g.p('stripe_count', 's.count', min=2, max=24)
    g.p('stripe_width', 's.width', min=0.1, max=0.9)
    g.p('stripe_count_pin', 'pin.count', min=2, max=24)
    palette(g, ([0.72, 0.66, 0.5], [0.55, 0.48, 0.32], [0.45, 0.22, 0.15]), ('color_a', 'color_b', 'pin_color'), ('ca', 'cb', 'cp'))
    blend(g, 'm1', 'ca', 'cb', 's')
    g.n('pin2', 'transform', {'in': 'pin'}, offset_u=0.0625)
    blend(g, 'm2', 'cp', 'm1', 'pin2')
    paper_texture(g, 'm2', 141, 0.15)
    rough_falling(g, 's', 0.75, 0.6, ('roughness_a', 'roughness_b'))
    finish(g, 'paper', 'rough', 'alb', 0.002)


wallpaper_stripes()


def wallpaper_damask():
    g = G('wallpaper_damask', 'wallpaper', 'Damask-like wallpaper: symmetric ornament of lobes on a tonal ground, slightly raised print.')
    g.n('b1', 'shape', count=4, shape='bell', size=0.9)
    g.n('w', 'fbm', scale_x=4, scale_y=4, octaves=2, roughness=0.5, seed=151)
    g.n('g1', 'gradient_radial', count=4, radius=1.0)
    g.n('ring', 'stripes', count=16, direction='v', width=0.5, softness=0.2)
    g.n('rw', 'warp', {'in': 'ring', 'height': 'g1'}, intensity=0.01)
    g.n('orn', 'blend', {'fg': 'rw', 'bg': 'b1'}, mode='multiply')
    g.n('d2', 'transform', {'in': 'orn'}, offset_u=0.125, offset_v=0.125)
    g.n('orn2', 'blend', {'fg': 'd2', 'bg': 'orn'}, mode='max')
    g.n('ornament', 'histogram_scan', {'in': 'orn2'}, position=0.35, contrast=0.8)
    g.p('ornament_size', 'b1.size', min=0.5, max=1.0)
    g.p('ornament_detail', 'rw.intensity', min=0.0, max=0.02)
    g.p('ornament_amount', 'ornament.position', min=0.1, max=0.6)
    two_tone(g, 'm', 'ornament', ([0.35, 0.08, 0.1], [0.5, 0.15, 0.15]), ('ground_color', 'ornament_color'))
    paper_texture(g, 'm', 152, 0.1, param=None)
    rough_range(g, 'ornament', 0.8, 0.45, ('roughness_ground', 'roughness_ornament'))
    finish(g, 'ornament', 'rough', 'alb', 0.003, shift=(1 / 16, 1 / 16))


wallpaper_damask()


def wallpaper_grasscloth():
    g = G('wallpaper_grasscloth', 'wallpaper', 'Grasscloth wallpaper: horizontal natural fibers.')
    g.n('f', 'fbm', scale_x=2, scale_y=128, octaves=3, roughness=0.6, seed=161)
    g.n('f2', 'fbm', scale_x=8, scale_y=32, octaves=3, roughness=0.5, seed=162)
    blend(g, 'm', 'f2', 'f', param='fiber_mix', mode='overlay', opacity=0.5)
    colors3(g, 'col', 'm', [0.35, 0.3, 0.2], [0.55, 0.48, 0.34], [0.7, 0.64, 0.5])
    finish(g, 'm', rough_falling(g, 'm', 0.85, 0.7), 'col', 0.004)


wallpaper_grasscloth()

# ---------------------------------------------------------------- brick
def brick(name, desc, col, mortar, rows, cols, seed):
    g = G(name, 'brick', desc)
    g.n('f', 'fbm', scale_x=16, scale_y=16, octaves=6, roughness=0.6, seed=seed)
    g.n('t', 'tile', {'pattern': 'f'}, layout='bricks', rows=rows, cols=cols, row_offset=0.5, gap=0.12, bevel=0.12, lum_var=0.6, seed=seed + 1)
    g.p('rows', 't.rows', min=rows // 2, max=rows * 2)
    g.p('mortar_width', 't.gap', min=0.02, max=0.3)
    g.p('edge_wear', 't.bevel', min=0.02, max=0.3)
    g.p('brick_variation', 't.lum_var')
    blend(g, 'm', 't.sampled', 't.random', param='brick_texture', mode='overlay', opacity=0.5)
    colors3(g, 'col', 'm', [c * 0.5 for c in col], col, [min(1, c * 1.3) for c in col], 0.5, 'brick')
    uniform(g, 'mc', mortar, 'mortar_color')
    g.n('edge', 'blend', {'fg': 'f', 'bg': 't.height'}, mode='multiply', opacity=0.4)
    g.n('mask', 'histogram_scan', {'in': 'edge'}, position=0.6, contrast=0.7)
    blend(g, 'alb', 'col', 'mc', 'mask')
    g.n('h', 'blend', {'fg': 'f', 'bg': 't.height'}, mode='multiply', opacity=0.3)
    finish(g, 'h', rough_range(g, 'f', 0.75, 0.95), 'alb', 0.008)


brick('brick_red', 'Red clay brick wall, running bond, grey mortar.', [0.4, 0.14, 0.08], [0.55, 0.53, 0.5], 12, 4, 171)
brick('brick_white_painted', 'Painted white brick wall.', [0.78, 0.77, 0.74], [0.7, 0.69, 0.66], 12, 4, 173)
brick('brick_yellow', 'Yellow / buff London stock brick, dark mortar.', [0.55, 0.42, 0.25], [0.3, 0.29, 0.27], 14, 4, 175)


def interlocking_pavers():
    # issue 18: interlocking concrete pavers (polyhaven brick_pavement_03): a running bond whose
    # long joints zigzag, so neighbouring pavers key into each other. The bond's maps are moved
    # along v by a trapezoid wave along u (soft stripes, two waves per paver length).
    g = G('brick_pavers_interlocking', 'brick', 'Interlocking concrete pavers (zigzag or "uni" '
          'pavers) in a running bond with sand joints.')
    g.n('f', 'fbm', scale_x=16, scale_y=16, octaves=6, roughness=0.6, seed=181)
    g.n('t', 'tile', {'pattern': 'f'}, layout='bricks', rows=8, cols=4, row_offset=0.5, gap=0.1, bevel=0.15,
        lum_var=0.4, seed=182)
    g.p('rows', 't.rows', min=4, max=16)
    g.p('joint_width', 't.gap', min=0.02, max=0.3)
    g.p('edge_chamfer', 't.bevel', min=0.02, max=0.3)
    g.p('paver_variation', 't.lum_var')
    g.n('wave', 'stripes', direction='u', count=8, width=0.5, softness=0.5)
    blend(g, 'm', 't.sampled', 't.random', param='paver_texture', mode='overlay', opacity=0.5)
    colors3(g, 'col', 'm', [0.18, 0.18, 0.17], [0.36, 0.35, 0.33], [0.5, 0.49, 0.46], 0.5, 'paver')
    uniform(g, 'jc', [0.16, 0.15, 0.14], 'joint_color')
    g.n('edge', 'blend', {'fg': 'f', 'bg': 't.height'}, mode='multiply', opacity=0.3)
    g.n('mask', 'histogram_scan', {'in': 'edge'}, position=0.65, contrast=0.7)
    blend(g, 'flat', 'col', 'jc', 'mask')
    g.n('alb', 'directional_warp', {'in': 'flat', 'height': 'wave'}, intensity=0.02, angle=0.25)
    g.n('h0', 'blend', {'fg': 'f', 'bg': 't.height'}, mode='multiply', opacity=0.3)
    g.n('h', 'directional_warp', {'in': 'h0', 'height': 'wave'}, intensity=0.02, angle=0.25)
    g.p('interlock_depth', 'alb.intensity', 'h.intensity', min=0.0, max=0.05,
        doc='how far the long joints zigzag (texture units)')
    # half a row down and a sixteenth across: the joints off the texture's border (tileability)
    finish(g, 'h', rough_range(g, 'f', 0.75, 0.95), 'alb', 0.008, shift=(1 / 16, 1 / 16))


interlocking_pavers()

# ---------------------------------------------------------------- fabric / carpet / leather
def fabric(name, desc, pattern, count, col, width, fuzziness, seed, cat='fabric', rough=(0.85, 0.95), shift=None):
    g = G(name, cat, desc)
    g.n('w', 'weave', count=count, pattern=pattern, width=width, seed=seed)
    g.p('thread_count', 'w.count', min=max(4, count // 2), max=count * 2)
    g.p('thread_width', 'w.width', min=0.5, max=1.0)
    fuzz(g, 'w.height', count * 2, fuzziness, seed + 1)
    blend(g, 'tv', 'w.random', 'hf', param='thread_variation', mode='overlay', opacity=0.3)
    warp_weft_colors(g, col, [c * 0.85 for c in col], 'w.warp', ids=('wc', 'fc'))
    shaded(g, 'cm', 'tv', 0.45, 'shadowing', 0.1)
    # shift: half a thread, so the border runs along thread centres, not between threads
    finish(g, 'hf', rough_range(g, 'hf', *rough), 'alb', 0.002, shift=(0.5 / count, 0.5 / count) if shift else None)


fabric('fabric_plain_weave', 'Plain-weave cotton / linen upholstery.', 'plain', 64, [0.55, 0.5, 0.42], 0.85, 0.3, 181)
fabric('fabric_twill', 'Twill (denim-like) fabric with diagonal ribs.', 'twill_2_2', 96, [0.12, 0.18, 0.35], 0.9, 0.25, 183)
fabric('fabric_basket', 'Basket-weave upholstery (panama), coarse.', 'basket_2_2', 48, [0.42, 0.36, 0.3], 0.85, 0.35, 185)
fabric('fabric_linen', 'Loose linen with slubby, irregular threads.', 'plain', 48, [0.68, 0.64, 0.56], 0.7, 0.6, 187)


def knit(name, desc, count, col, seed, fuzz_scale, shadow, relief, shift=None):
    """Knitted fabric: columns of V-shaped stitches (bell-shaped loops over alternating diagonals)."""
    g = G(name, 'fabric', desc)
    g.n('sh', 'shape', count=count, shape='bell', size=1.0)
    diagonals(g, ('zig', 'zig2'), count, 0.5, 0.3)
    g.n('col', 'gradient_linear', direction='u', repeats=count, shape='saw')
    blend(g, 'vv', 'zig', 'zig2', 'col')
    blend(g, 'st', 'sh', 'vv', param='stitch_roundness', mode='multiply', opacity=0.5)
    g.p('stitch_softness', 'zig.softness', min=0.05, max=0.5)
    fuzz(g, 'st', fuzz_scale, 0.3, seed, id='h')
    tinted(g, 'c', col, 'yarn_color', 'h', shadow, 'shadowing', 0.1, sh='s')
    finish(g, 'h', rough_falling(g, 'h', 0.95, 0.85), 'alb', relief, shift=shift)


knit('fabric_knit', 'Knitted fabric: columns of V-shaped stitches.', 24, [0.5, 0.12, 0.1], 191, 64, 0.4, 0.003)


def velvet():
    g = G('fabric_velvet', 'fabric', 'Velvet: dense pile with soft, directional sheen patches.')
    g.n('f', 'fbm', scale_x=3, scale_y=3, octaves=4, roughness=0.5, seed=201)
    g.n('pile', 'fbm', scale_x=128, scale_y=128, octaves=2, roughness=0.5, seed=202)
    g.n('dirb', 'directional_blur', {'in': 'f'}, length=0.05, angle=0.2, taps=8)
    g.p('crush_direction', 'dirb.angle')
    g.p('crush_length', 'dirb.length', min=0.0, max=0.15)
    blend(g, 'm', 'pile', 'dirb', mode='overlay', opacity=0.3)
    colors3(g, 'col', 'm', [0.13, 0.035, 0.045], [0.18, 0.05, 0.062], [0.25, 0.078, 0.092])
    finish(g, 'm', rough_range(g, 'm', 0.7, 0.9), 'col', 0.003)


velvet()


def pile(g, seed, scale=256, exposed=True):
    """Cut pile: slightly blurred white noise (node 'pb'), the tufts' softness exposed if `exposed`."""
    g.n('pn', 'white_noise', scale=scale, seed=seed)
    g.n('pb', 'blur', {'in': 'pn'}, sigma=0.0015)
    if exposed:
        g.p('tuft_softness', 'pb.sigma', min=0.0005, max=0.005)
    return 'pb'


def carpet(name, desc, col, scale, loop, seed):
    g = G(name, 'carpet', desc)
    if loop:
        g.n('s', 'shape', count=scale, shape='bell', size=1.0)
        g.n('o', 'transform', {'in': 's'}, offset_u=0.5 / scale)
        g.n('p', 'blend', {'fg': 'o', 'bg': 's', 'mask': 'rowm'})
        g.n('rowm', 'stripes', count=scale // 2, direction='v', width=0.5, softness=0.01)
        g.p('loop_size', 's.size', min=0.5, max=1.0)
        tufts = 'p'
    else:
        tufts = pile(g, seed, scale * 4)
    g.n('f', 'fbm', scale_x=4, scale_y=4, octaves=4, roughness=0.5, seed=seed + 1)
    blend(g, 'm', 'f', tufts, param='mottling', mode='overlay', opacity=0.5)
    g.n('c', 'gradient_map', {'in': 'm'}, color_0=[c * 0.5 for c in col], color_1=col, color_2=[min(1, c * 1.4) for c in col])
    g.p('pile_color', 'c.color_1')
    g.p('pile_shadow', 'c.color_0')
    g.p('pile_tip', 'c.color_2')
    finish(g, 'm', rough_range(g, 'm', 0.9, 1.0, ('roughness_min',)), 'c', 0.004)


carpet('carpet_loop_pile', 'Berber-like loop pile carpet in rows.', [0.45, 0.4, 0.33], 48, True, 211)
carpet('carpet_cut_pile', 'Cut pile (plush) carpet, fine speckle.', [0.3, 0.32, 0.38], 64, False, 213)


def rug_pile(g, design, seed, opacity, disorder=True, exposed=True, **finish_kw):
    """Finishes a rug: the `design` on cut pile (warped by the tufts if `disorder`), the pile's texture
    overlaid, matte; `exposed`: the tufts' softness and the roughness exposed (the first rug has neither)."""
    p = pile(g, seed, exposed=exposed)
    if disorder:
        g.n('wr', 'warp', {'in': design, 'height': p}, intensity=0.0005)
        g.p('pile_disorder', 'wr.intensity', min=0.0, max=0.002)
        design = 'wr'
    blend(g, 'alb', p, design, param='pile_texture', mode='overlay', opacity=opacity)
    finish(g, p, rough_range(g, p, 0.9, 1.0, ('roughness_min',) if exposed else ()), 'alb', 0.003, **finish_kw)


def rug():
    g = G('carpet_patterned_rug', 'carpet', 'Patterned rug: bordered diamonds over cut pile.')
    g.n('d', 'checker', count=8, softness=0.02)
    diagonals(g, ('dr', 'dr2'), 8, 0.3, 0.05)
    g.n('dd', 'blend', {'fg': 'dr', 'bg': 'dr2'}, mode='max')
    g.p('motif_line_width', 'dr.width', min=0.1, max=0.6)
    three_tone(g, ([0.45, 0.08, 0.06], [0.08, 0.1, 0.25], [0.75, 0.65, 0.45]), ('field_color', 'motif_color', 'line_color'),
               ('d', 'dd'))
    rug_pile(g, 'm2', 221, 0.3, exposed=False)


rug()


def leather(name, desc, col, scale, rough, seed):
    g = G(name, 'leather', desc)
    g.n('v', 'voronoi', scale=scale, jitter=1.0, mode='f2_minus_f1', seed=seed)
    g.n('cr', 'histogram_scan', {'in': 'v'}, position=0.8, contrast=0.6)
    g.p('crease_width', 'cr.position', min=0.5, max=0.98)
    g.n('f', 'fbm', scale_x=4, scale_y=4, octaves=5, roughness=0.55, seed=seed + 1)
    blend(g, 'm', 'f', 'cr', param='wear', mode='overlay', opacity=0.4)
    colors3(g, 'col', 'm', [c * 0.5 for c in col], col, [min(1, c * 1.3) for c in col], 0.5, 'leather')
    rough_range(g, 'cr', rough[1], rough[0], ('roughness_grain', 'roughness_top'))
    finish(g, 'cr', 'rough', 'col', 0.004)


leather('leather_brown', 'Brown pebbled leather (sofa, chair).', [0.25, 0.12, 0.06], 48, (0.45, 0.65), 231)
leather('leather_black', 'Black smooth leather, fine grain, semi-gloss.', [0.04, 0.035, 0.035], 80, (0.3, 0.5), 233)

# ---------------------------------------------------------------- metal / plastic / cork / rubber / paper
def brushed_metal():
    g = G('metal_brushed', 'metal', 'Brushed stainless steel / aluminium: fine streaks along u.')
    g.n('n', 'fbm', scale_x=2, scale_y=256, octaves=3, roughness=0.6, seed=241)
    g.n('b', 'directional_blur', {'in': 'n'}, length=0.05, angle=0.0, taps=8)
    g.p('streak_length', 'b.length', min=0.0, max=0.15)
    g.n('lv', 'levels', {'in': 'b'}, in_low=0.2, in_high=0.8)
    colors3(g, 'col', 'lv', [0.5, 0.5, 0.52], [0.62, 0.62, 0.64], [0.72, 0.72, 0.74], 0.5, 'metal')
    rough_range(g, 'lv', 0.25, 0.4)
    finish(g, 'lv', 'rough', 'col', 0.0005, metallic=fully_metallic(g))


brushed_metal()


def painted_metal():
    g = G('metal_painted', 'metal', 'Powder-coated / painted metal with slight orange peel and chips.')
    g.n('op', 'fbm', scale_x=48, scale_y=48, octaves=3, roughness=0.5, seed=251)
    g.n('ch', 'fbm', scale_x=6, scale_y=6, octaves=6, roughness=0.6, seed=252)
    g.n('chips', 'histogram_scan', {'in': 'ch'}, position=0.1, contrast=0.9)
    g.p('chipping', 'chips.position', min=0.0, max=0.4)
    two_tone(g, 'alb', 'chips', ([0.1, 0.25, 0.2], [0.6, 0.6, 0.62]), ('paint_color', 'metal_color'), ('paint', 'bare'))
    g.n('inv', 'invert', {'in': 'chips'})
    g.n('h', 'blend', {'fg': 'op', 'bg': 'inv'}, mode='multiply', opacity=0.1)
    rough_range(g, 'chips', 0.35, 0.5, ('roughness_paint', 'roughness_bare'))
    finish(g, 'h', 'rough', 'alb', 0.003, metallic=metallic_where(g, 'chips', 0.9, 'bare_metallic'))


painted_metal()

for name, desc, col, rough, relief, scale, seed in [
        ('plastic_glossy', 'Glossy molded plastic (appliances, furniture).', [0.8, 0.8, 0.78], (0.05, 0.1), 0.0005, 8, 261),
        ('plastic_textured', 'Textured (sand-blasted) matte plastic.', [0.15, 0.15, 0.16], (0.5, 0.65), 0.006, 96, 263),
        ('plastic_laminate', 'Colored laminate worktop with fine speckle.', [0.55, 0.2, 0.15], (0.25, 0.35), 0.002, 128, 265)]:
    tinted_fbm(name, 'plastic', desc, col, 'color', 0.97, scale, rough, relief, seed)


def cork():
    g = G('cork', 'cork', 'Agglomerated cork board / floor: granules of varied brown.')
    g.n('v', 'voronoi', scale=64, jitter=1.0, mode='cell_value', seed=271)
    g.n('e', 'voronoi', scale=64, jitter=1.0, mode='f2_minus_f1', seed=271)
    g.n('ed', 'histogram_scan', {'in': 'e'}, position=0.85, contrast=0.6)
    g.p('granule_gaps', 'ed.position', min=0.6, max=1.0)
    g.n('f', 'fbm', scale_x=16, scale_y=16, octaves=4, roughness=0.5, seed=272)
    blend(g, 'm', 'f', 'v', mode='overlay', opacity=0.5)
    blend(g, 'm2', 'ed', 'm', param='gap_darkness', mode='multiply', opacity=0.6)
    colors3(g, 'col', 'm2', [0.2, 0.12, 0.06], [0.45, 0.3, 0.17], [0.62, 0.45, 0.28])
    finish(g, 'm2', rough_range(g, 'm', 0.8, 0.9), 'col', 0.005)


cork()


def rubber():
    g = G('rubber_studded', 'rubber', 'Studded rubber flooring: round raised studs on a matte base.')
    g.n('s', 'shape', count=12, shape='disc', size=0.55, softness=0.08)
    g.p('stud_count', 's.count', min=4, max=32)
    g.p('stud_size', 's.size', min=0.2, max=0.9)
    g.p('stud_edge', 's.softness', min=0.02, max=0.3)
    g.n('f', 'fbm', scale_x=64, scale_y=64, octaves=3, roughness=0.5, seed=281)
    g.n('h', 'blend', {'fg': 'f', 'bg': 's'}, mode='add', opacity=0.03)
    tinted(g, 'c', [0.08, 0.08, 0.085], 'rubber_color', 'f', 0.85)
    rough_range(g, 's', 0.8, 0.6, ('roughness_base', 'roughness_stud'))
    finish(g, 'h', 'rough', 'alb', 0.01)


rubber()


def rubber_plain():
    g = G('rubber_plain', 'rubber', 'Plain rubber / linoleum sheet with fine flecks.')
    g.n('f', 'white_noise', scale=512, seed=291)
    g.n('fl', 'histogram_scan', {'in': 'f'}, position=0.06, contrast=0.95)
    g.p('fleck_amount', 'fl.position', min=0.0, max=0.3)
    two_tone(g, 'alb', 'fl', ([0.35, 0.38, 0.33], [0.75, 0.75, 0.72]), ('base_color', 'fleck_color'), ('c', 'fc'))
    g.n('b', 'fbm', scale_x=16, scale_y=16, octaves=4, roughness=0.5, seed=292)
    finish(g, 'b', rough_range(g, 'b', 0.55, 0.7), 'alb', 0.002, shift=(1 / 1024, 1 / 1024), snap=False)


rubber_plain()


def paper(name, desc, col, fibers, seed, corrugated=False):
    g = G(name, 'paper', desc)
    g.n('f', 'fbm', scale_x=fibers, scale_y=fibers, octaves=5, roughness=0.6, seed=seed)
    tinted(g, 'c', col, 'paper_color', 'f', 0.9, 'mottling', 0.6)
    h = 'f'
    if corrugated:
        g.n('rib', 'stripes', count=24, direction='v', width=0.5, softness=0.4)
        g.n('hh', 'blend', {'fg': 'f', 'bg': 'rib'}, mode='multiply', opacity=0.2)
        g.p('rib_count', 'rib.count', min=8, max=64)
        h = 'hh'
    finish(g, h, rough_range(g, 'f', 0.8, 0.95), 'alb', 0.002, shift=(0, 1 / 96) if corrugated else None)


paper('paper_white', 'White paper / card with fiber mottling.', [0.82, 0.81, 0.78], 32, 301)
paper('paper_cardboard', 'Brown corrugated cardboard.', [0.45, 0.33, 0.2], 24, 303, corrugated=True)


def homogeneous():
    g = G('homogeneous', 'homogeneous', 'Homogeneous material: one albedo, one roughness, flat normal (the paper\'s fallback for small parts).')
    g.n('c', 'uniform_color', color=[0.5, 0.5, 0.5])
    g.n('r', 'uniform_gray', value=0.5)
    g.n('h', 'uniform_gray', value=0.5)
    g.n('m', 'uniform_gray', value=0.0)
    g.p('albedo', 'c.color')
    g.p('roughness', 'r.value')
    g.p('metallic', 'm.value')
    g.p('flat_height', 'h.value', doc='constant height (no effect on the normal)')
    finish(g, 'h', 'r', 'c', 0.02, metallic='m')


homogeneous()

# ================================================================ issue 18: a larger library
# Looks that the photographed textures (../shared/data/textures) showed no graph for: yarn-dyed
# fabric patterns, quilting, natural-fibre floor coverings, panelling and special wood grains,
# patterned rugs, ceiling tiles, stone walls, wallpaper motifs, perforated metal, woven vinyl.

def yarn_dyed(name, desc, weave, threads, stripe_count, colors, width=0.5, pin=None, seed=401, rough=(0.8, 0.95)):
    """Yarn-dyed cloth: warp threads carry a colour stripe sequence along u, weft threads the same
    along v; the weave's warp mask picks which one shows, so checks, gingham, houndstooth (2/2
    twill, 4 dark / 4 light threads) and tartans come out of the weave itself."""
    g = G(name, 'fabric', desc)
    g.n('w', 'weave', count=threads, pattern=weave, width=0.9, seed=seed)
    g.p('thread_width', 'w.width', min=0.6, max=1.0)
    fuzz(g, 'w.height', min(256, threads * 2), 0.25, seed + 1)
    for direction in 'uv':
        g.n('s' + direction, 'stripes', count=stripe_count, direction=direction, width=width, softness=0.002)
    g.p('stripe_width', 'su.width', 'sv.width', min=min(0.2, width), max=0.8)
    two_tone(g, 'cu', 'su', colors[:2], ('ground_color', 'stripe_color'))
    blend(g, 'cv', 'cb', 'ca', 'sv')
    cu, cv = 'cu', 'cv'
    if pin is not None:  # a second, narrow stripe (tartan over-check)
        for direction in 'uv':
            g.n('p' + direction, 'stripes', count=pin[0], direction=direction, width=pin[1], softness=0.002)
        g.p('overcheck_width', 'pu.width', 'pv.width', min=0.05, max=0.4)
        uniform(g, 'cp', colors[2], 'overcheck_color')
        cu, cv = blend(g, 'cu2', 'cp', 'cu', 'pu'), blend(g, 'cv2', 'cp', 'cv', 'pv')
    blend(g, 'cm', cu, cv, 'w.warp')
    shaded(g, 'cm', 'hf', 0.55, 'shadowing', 0.2)
    finish(g, 'hf', rough_range(g, 'hf', *rough), 'alb', 0.002)


yarn_dyed('fabric_gingham', 'Gingham: plain-weave cotton, white and one colour in equal checks (mixed tone where they cross).',
          'plain', 128, 8, [[0.8, 0.8, 0.78], [0.55, 0.08, 0.08]])
yarn_dyed('fabric_buffalo_check', 'Buffalo check: large black and red blocks in a 2/2 twill wool (flannel shirts, blankets).',
          'twill_2_2', 96, 3, [[0.45, 0.03, 0.03], [0.015, 0.015, 0.015]], seed=403)
yarn_dyed('fabric_houndstooth', 'Houndstooth: 2/2 twill with 4 dark and 4 light threads each way (the broken-check teeth come from the weave).',
          'twill_2_2', 128, 16, [[0.78, 0.76, 0.72], [0.03, 0.03, 0.03]], seed=405)
yarn_dyed('fabric_tartan', 'Tartan / plaid: a 2/2 twill with wide bands and a narrow over-check in a third colour, the same sett both ways.',
          'twill_2_2', 128, 4, [[0.05, 0.18, 0.1], [0.04, 0.06, 0.2], [0.6, 0.1, 0.06]], width=0.4, pin=(8, 0.12), seed=407)
yarn_dyed('fabric_windowpane', 'Windowpane check: thin coloured lines on a plain ground (shirting, suiting).',
          'plain', 128, 4, [[0.62, 0.6, 0.55], [0.12, 0.15, 0.3]], width=0.08, seed=409)


def fabric_herringbone():
    g = G('fabric_herringbone', 'fabric', 'Herringbone tweed: 2/2 twill reversed in vertical bands (zig-zag), two-tone yarns.')
    g.n('w', 'weave', count=96, pattern='twill_2_2', width=0.9, seed=411)
    g.p('thread_width', 'w.width', min=0.6, max=1.0)
    g.n('h2', 'transform', {'in': 'w.height'}, rotation='90')
    g.n('m2', 'transform', {'in': 'w.warp'}, rotation='90')
    g.n('band', 'stripes', count=8, direction='u', width=0.5, softness=0.002)
    blend(g, 'h', 'h2', 'w.height', 'band')
    blend(g, 'm', 'm2', 'w.warp', 'band')
    fuzz(g, 'h', 192, 0.3, 412)
    warp_weft_colors(g, [0.12, 0.11, 0.1], [0.45, 0.42, 0.37], 'm')
    shaded(g, 'cm', 'hf', 0.5, 'shadowing', 0.2)
    finish(g, 'hf', rough_range(g, 'hf', 0.85, 0.95), 'alb', 0.002)


fabric_herringbone()


def quilted(name, desc, count, col, tufted=False, seed=421):
    """Diamond quilting: puffs between diagonal stitch lines (the product of two triangle waves);
    tufted: deeper puffs and a button at every stitch crossing."""
    g = G(name, 'fabric', desc)
    diagonals(g, ('d1', 'd2'), count, 0.5, 0.5)
    g.n('pf', 'blend', {'fg': 'd1', 'bg': 'd2'}, mode='multiply')
    g.n('puff', 'levels', {'in': 'pf'}, gamma=2.5 if tufted else 1.8)
    g.p('puffiness', 'puff.gamma', min=1.0, max=4.0)
    g.n('w', 'weave', count=128, pattern='plain', width=0.9, seed=seed)
    blend(g, 'hs', 'w.height', 'puff', param='weave_relief', mode='add', opacity=0.06, min=0.0, max=0.2)
    tinted(g, 'c', col, 'cloth_color', 'puff', 0.45 if tufted else 0.65, 'fold_shadow', 0.1, out='alb0')
    alb, h = 'alb0', 'hs'
    if tufted:
        g.n('bt', 'shape', count=count, shape='disc', size=0.12, softness=0.04)
        uniform(g, 'btc', [c * 0.5 for c in col], 'button_color')
        alb = blend(g, 'alb', 'btc', 'alb0', 'bt')
        h = blend(g, 'hb', 'bt', 'hs', mode='add', opacity=0.2)
    rough_range(g, 'puff', 0.95, 0.8, ('roughness_folds', 'roughness_top'))
    finish(g, h, 'rough', alb, 0.02 if tufted else 0.012, normal_max=0.1)


quilted('fabric_quilted', 'Diamond-quilted upholstery / bedspread: soft puffs between stitched diagonal lines.', 6, [0.55, 0.5, 0.45])
quilted('fabric_tufted', 'Tufted (capitonne) upholstery: deep diamond puffs with a button at every crossing.', 4, [0.12, 0.2, 0.15], True, 423)


def corduroy():
    g = G('fabric_corduroy', 'fabric', 'Corduroy: parallel rounded pile ribs (wales) along v.')
    g.n('rib', 'stripes', count=24, direction='u', width=0.7, softness=0.5)
    g.p('wale_count', 'rib.count', min=8, max=64)
    g.p('wale_width', 'rib.width', min=0.3, max=0.95)
    g.n('pile', 'fbm', scale_x=128, scale_y=32, octaves=3, roughness=0.5, seed=431)
    blend(g, 'h', 'pile', 'rib', param='pile_texture', mode='overlay', opacity=0.3)
    colors3(g, 'col', 'h', [0.18, 0.1, 0.05], [0.32, 0.19, 0.1], [0.42, 0.27, 0.15], 0.5, 'pile')
    rough_range(g, 'h', 0.95, 0.8, ('roughness_groove', 'roughness_top'))
    finish(g, 'h', 'rough', 'col', 0.004, shift=(0.5 / 24, 0))  # the border on a wale's crest, not in a groove's cusp


corduroy()

knit('fabric_knit_chunky', 'Chunky hand knit (throws, cushions): large V stitches of thick wool.', 8, [0.72, 0.7, 0.64], 441,
     min(256, 8 * 4), 0.35, 0.006, shift=(0.5 / 8, 0.5 / 8))

fabric('fabric_canvas', 'Heavy cotton canvas / duck: coarse, tight plain weave.', 'plain', 40, [0.6, 0.55, 0.45], 0.95, 0.25, 451)


# ---------------------------------------------------------------- floor coverings (carpet)
fabric('carpet_sisal', 'Sisal rug: coarse 2/2 basket weave of stiff, light fibres.', 'basket_2_2', 32,
       [0.6, 0.5, 0.34], 0.95, 0.45, 461, cat='carpet', rough=(0.8, 0.95), shift=True)
fabric('carpet_jute', 'Chunky jute rug: thick, hairy plain-weave cords, golden brown.', 'plain', 16,
       [0.5, 0.37, 0.2], 0.98, 0.55, 463, cat='carpet', rough=(0.85, 0.97), shift=True)
fabric('carpet_seagrass', 'Seagrass / woven vinyl-look floor covering: tight 3/1 twill of smooth strands.', 'twill_3_1', 48,
       [0.45, 0.45, 0.3], 0.95, 0.2, 465, cat='carpet', rough=(0.5, 0.7), shift=True)


def tatami():
    g = G('carpet_tatami', 'carpet', 'Tatami: mats of fine woven rush (ribs across the mat) edged with dark cloth borders.')
    g.n('rib', 'weave', count=160, pattern='plain', width=0.95, seed=471)
    g.n('rush', 'fbm', scale_x=4, scale_y=160, octaves=3, roughness=0.6, seed=472)
    blend(g, 'rf', 'rush', 'rib.height', param='rush_variation', mode='overlay', opacity=0.4)
    g.n('t', 'tile', {'pattern': 'rf'}, layout='grid', rows=1, cols=2, gap=0.0, bevel=0.02, lum_var=0.2, seed=473)
    g.n('edge', 'tile', layout='grid', rows=1, cols=2, gap=0.0, bevel=0.005, lum_var=0.0, seed=474)
    g.n('bm', 'histogram_scan', {'in': 't.height'}, position=0.9, contrast=0.9)
    g.p('border_width', 'bm.position', min=0.7, max=1.0)
    colors3(g, 'col', 't.sampled', [0.35, 0.33, 0.17], [0.55, 0.52, 0.3], [0.68, 0.64, 0.42], 0.5, 'rush')
    over_ground(g, 'col', 'bc', [0.05, 0.06, 0.05], 'border_color', 'bm')
    g.n('h', 'blend', {'fg': 't.sampled', 'bg': 'bm'}, mode='multiply', opacity=0.3)
    finish(g, 'h', rough_range(g, 't.sampled', 0.55, 0.75), 'alb', 0.004, shift=(0.25, 0.5))


tatami()


def rug_striped():
    g = G('carpet_striped_rug', 'carpet', 'Striped rug / runner: bands of three colours across a cut or flat-woven pile.')
    g.n('s1', 'stripes', count=4, direction='v', width=0.5, softness=0.01)
    g.n('s2', 'stripes', count=12, direction='v', width=0.3, softness=0.01)
    g.p('band_width', 's1.width', min=0.2, max=0.8)
    g.p('pinstripe_width', 's2.width', min=0.05, max=0.6)
    three_tone(g, ([0.7, 0.66, 0.58], [0.12, 0.16, 0.25], [0.5, 0.2, 0.1]), ('ground_color', 'band_color', 'stripe_color'),
               ('s1', 's2'))
    rug_pile(g, 'm2', 481, 0.35, shift=(0, 1 / 32))


rug_striped()


def rug_medallion():
    g = G('carpet_medallion_rug', 'carpet', 'Bordered rug: a field with a central diamond medallion, framed by a border band (one rug per texture tile).')
    triangle_waves(g, 1)
    # frame: distance to the rug's edge = min of the two triangles (0 at the edge, 1 at the centre)
    g.n('fr', 'blend', {'fg': 'tu', 'bg': 'tv'}, mode='min')
    g.n('border', 'histogram_scan', {'in': 'fr'}, position=0.85, contrast=0.97)
    g.p('border_width', 'border.position', min=0.7, max=0.97)
    g.n('line', 'histogram_scan', {'in': 'fr'}, position=0.8, contrast=0.97)
    # medallion: the L1 distance to the centre (mean of the two triangles)
    g.n('dia', 'blend', {'fg': 'tu', 'bg': 'tv'}, mode='copy', opacity=0.5)
    g.n('med', 'histogram_scan', {'in': 'dia'}, position=0.25, contrast=0.97)
    g.p('medallion_size', 'med.position', min=0.05, max=0.5)
    palette(g, ([0.42, 0.06, 0.05], [0.06, 0.08, 0.2], [0.72, 0.62, 0.45]), ('field_color', 'border_color', 'ornament_color'))
    g.n('motif', 'stripes', count=32, direction='diagonal', width=0.25, softness=0.1)
    blend(g, 'mf', 'cc', 'ca', 'motif', param='field_pattern', opacity=0.3)
    blend(g, 'a1', 'cb', 'mf', 'med')
    g.n('ib', 'invert', {'in': 'border'})
    blend(g, 'a2', 'cb', 'a1', 'ib')
    g.n('il', 'invert', {'in': 'line'})
    g.n('lm', 'blend', {'fg': 'il', 'bg': 'border'}, mode='multiply')
    blend(g, 'a3', 'cc', 'a2', 'lm')
    rug_pile(g, 'a3', 491, 0.3, disorder=False)


rug_medallion()


def shag():
    g = G('carpet_shag', 'carpet', 'Shag rug: long, loose strands lying in random directions.')
    g.n('n', 'white_noise', scale=192, seed=501)
    g.n('b1', 'directional_blur', {'in': 'n'}, length=0.03, angle=0.12, taps=12)
    g.n('f', 'fbm', scale_x=6, scale_y=6, octaves=3, roughness=0.5, seed=502)
    g.n('b2', 'directional_warp', {'in': 'b1', 'height': 'f'}, intensity=0.05, angle=0.3)
    g.p('strand_length', 'b1.length', min=0.005, max=0.06)
    g.p('strand_direction', 'b1.angle')
    g.p('strand_swirl', 'b2.intensity', min=0.0, max=0.1)
    g.n('lv', 'levels', {'in': 'b2'}, in_low=0.3, in_high=0.7)
    colors3(g, 'col', 'lv', [0.3, 0.28, 0.25], [0.55, 0.52, 0.47], [0.75, 0.72, 0.66], 0.5, 'pile')
    finish(g, 'lv', rough_falling(g, 'lv', 0.95, 0.85), 'col', 0.004)


shag()


# ---------------------------------------------------------------- ceiling and patterned tiles
def ceiling_tile(name, desc, holes, seed):
    """Suspended-ceiling tiles in a grid: a fissured mineral-fibre face, or a perforated one."""
    g = G(name, 'tile', desc)
    g.n('t', 'tile', layout='grid', rows=2, cols=2, gap=0.02, bevel=0.015, lum_var=0.05, seed=seed)
    g.p('grid_width', 't.gap', min=0.0, max=0.08)
    g.p('tile_variation', 't.lum_var')
    if holes:
        g.n('pit', 'shape', count=48, shape='disc', size=0.3, softness=0.1)
        g.p('hole_size', 'pit.size', min=0.1, max=0.6)
    else:
        g.n('v', 'voronoi', scale=24, jitter=1.0, mode='f2_minus_f1', seed=seed + 1)
        g.n('pit0', 'histogram_scan', {'in': 'v'}, position=0.15, contrast=0.85)
        g.n('pit', 'invert', {'in': 'pit0'})
        g.p('fissures', 'pit0.position', min=0.02, max=0.4)
    g.n('f', 'fbm', scale_x=64, scale_y=64, octaves=3, roughness=0.5, seed=seed + 2)
    g.n('face', 'blend', {'fg': 'f', 'bg': 'pit'}, mode='overlay', opacity=0.2)
    g.n('fh', 'blend', {'fg': 'face', 'bg': 't.height'}, mode='multiply', opacity=1.0)
    g.n('depth', 'blend', {'fg': 'pit', 'bg': 'fh'}, mode='subtract', opacity=0.5)
    palette(g, ([0.8, 0.79, 0.76], [0.85, 0.85, 0.85], [0.25, 0.24, 0.22]), ('tile_color', 'grid_color', 'hole_color'),
            ('tc', 'gc', 'pc'))
    blend(g, 'a0', 'pc', 'tc', 'pit', param='hole_darkness', opacity=0.8)
    blend(g, 'alb', 'a0', 'gc', 't.height')
    rough_range(g, 't.height', 0.4, 0.95, ('roughness_grid', 'roughness_tile'))
    finish(g, 'depth', 'rough', 'alb', 0.004, shift=(0.25, 0.25))


ceiling_tile('tile_ceiling_fissured', 'Acoustic ceiling tiles (mineral fibre): white faces with random fissures, in a T-bar grid.', False, 511)
ceiling_tile('tile_ceiling_perforated', 'Perforated acoustic ceiling tiles: a regular grid of small holes, white grid.', True, 513)


def tile_herringbone():
    g = G('tile_herringbone', 'tile', 'Ceramic / porcelain tiles laid in herringbone with grout joints.')
    g.n('hb', 'herringbone', count=4, ratio=3, gap=0.12, bevel=0.1, lum_var=0.3, seed=521)
    joint_params(g, 'hb', grout=(0.02, 0.3), bevel=(0.02, 0.3))
    mottled(g, 'hb.random', 8, 0.3, octaves=4, seed=522)
    colors3(g, 'tc', 'var', [0.42, 0.45, 0.44], [0.55, 0.58, 0.57], [0.66, 0.69, 0.68], 0.5, 'tile')
    over_ground(g, 'tc', 'gc', [0.6, 0.6, 0.58], 'grout_color', 'hb.height')
    grout_rough(g, 'hb.height', 0.15)
    finish(g, 'hb.height', 'rough', 'alb', 0.008, shift=(1 / 64, 1 / 64))


tile_herringbone()


def zellige():
    g = G('tile_zellige', 'tile', 'Zellige: small handmade glazed tiles, strongly varied in tone, wavy glossy faces, thin joints.')
    g.n('t', 'tile', layout='grid', rows=8, cols=8, gap=0.04, bevel=0.08, lum_var=0.8, seed=531)
    joint_params(g, 't', grout=(0.0, 0.2), bevel=None)
    mottled(g, 't.random', 16, 0.5, octaves=4, seed=532, cloud='wave', param='glaze_pooling')
    colors3(g, 'tc', 'var', [0.05, 0.2, 0.22], [0.12, 0.38, 0.4], [0.4, 0.62, 0.6], 0.5, 'glaze')
    over_ground(g, 'tc', 'gc', [0.7, 0.68, 0.63], 'grout_color', 't.height')
    blend(g, 'h', 'wave', 't.height', param='face_waviness', mode='multiply', opacity=0.4)
    grout_rough(g, 't.height', 0.06, 'glaze')
    finish(g, 'h', 'rough', 'alb', 0.01, shift=(1 / 16, 1 / 16))


zellige()


def encaustic():
    g = G('tile_encaustic', 'tile', 'Encaustic / cement pattern tiles: a two-colour star-and-diamond motif repeated on every tile.')
    g.n('t', 'tile', layout='grid', rows=4, cols=4, gap=0.02, bevel=0.02, lum_var=0.1, seed=541)
    g.p('grout_width', 't.gap', min=0.0, max=0.1)
    triangle_waves(g, 4)
    g.n('dia', 'blend', {'fg': 'tu', 'bg': 'tv'}, mode='copy', opacity=0.5)
    g.n('m1', 'histogram_scan', {'in': 'dia'}, position=0.45, contrast=0.95)
    g.p('diamond_size', 'm1.position', min=0.2, max=0.7)
    g.n('sq', 'blend', {'fg': 'tu', 'bg': 'tv'}, mode='max')
    g.n('m2', 'histogram_scan', {'in': 'sq'}, position=0.3, contrast=0.95)
    g.p('star_size', 'm2.position', min=0.1, max=0.5)
    three_tone(g, ([0.75, 0.73, 0.68], [0.1, 0.16, 0.3], [0.6, 0.35, 0.2]), ('ground_color', 'motif_color', 'accent_color'),
               ('m1', 'm2'), ('a1', 'a2'))
    g.n('f', 'fbm', scale_x=16, scale_y=16, octaves=4, roughness=0.5, seed=542)
    blend(g, 'a3', 'f', 'a2', param='wear', mode='overlay', opacity=0.15)
    uniform(g, 'gc', [0.55, 0.53, 0.5])
    blend(g, 'alb', 'a3', 'gc', 't.height')
    finish(g, 't.height', rough_range(g, 'f', 0.5, 0.7), 'alb', 0.004, shift=(1 / 8, 1 / 8))


encaustic()

# ---------------------------------------------------------------- wood: grains, panelling, laminate
def cathedral_grain(g, seed):
    """Flat-sawn grain: rings bent into nested arches (the 'cathedrals') by a triangle ramp
    across each plank-wide band, then wavy."""
    g.n('ring', 'stripes', count=24, direction='v', width=0.35, softness=0.35)
    g.n('tri', 'gradient_linear', direction='u', repeats=2, shape='triangle')
    g.n('arch', 'levels', {'in': 'tri'}, gamma=0.45)  # rounds the triangle's tip into an arch
    g.n('arched', 'directional_warp', {'in': 'ring', 'height': 'arch'}, intensity=0.12, angle=0.25)
    g.p('arch_height', 'arched.intensity', min=0.0, max=0.2)
    return wavy_fibers(g, 'arched', seed, 2, 0.03, 0.3)


def quarter_sawn_grain(g, seed):
    """Quarter-sawn: tight straight rings with the medullary-ray flecks (short light streaks)."""
    g.n('ring', 'stripes', count=96, direction='v', width=0.4, softness=0.3)
    g.n('fib', 'fbm', scale_x=4, scale_y=128, octaves=3, roughness=0.6, seed=seed)
    blend(g, 'rg', 'fib', 'ring', param='fiber_strength', mode='overlay', opacity=0.4)
    g.n('fl', 'fbm', scale_x=16, scale_y=64, octaves=3, roughness=0.5, seed=seed + 3)
    g.n('fleck', 'histogram_scan', {'in': 'fl'}, position=0.2, contrast=0.85)
    g.p('ray_flecks', 'fleck.position', min=0.0, max=0.5)
    return blend(g, 'grain', 'fleck', 'rg', param='fleck_strength', mode='screen', opacity=0.6)


def laminate_grain(g, seed):
    """Printed laminate: one short grain print repeated (visible repeats along each plank)."""
    base = wood_grain(g, rings=18, seed=seed, warp=0.03)
    g.n('print', 'transform', {'in': base}, tile=4)
    return 'print'


wood_planks('wood_cathedral_oak', 'Flat-sawn oak planks with strong cathedral (arched) grain.', cathedral_grain, 4, 1, 'planks',
            ((0.56, 0.36, 0.18), (0.40, 0.23, 0.10), (0.24, 0.12, 0.05)), 551)
wood_planks('wood_quarter_sawn', 'Quarter-sawn oak: straight tight grain with silvery ray flecks.', quarter_sawn_grain, 6, 2, 'planks',
            ((0.6, 0.42, 0.24), (0.45, 0.3, 0.15), (0.3, 0.18, 0.08)), 553, shift=(1 / 64, 2 / 64))
wood_planks('wood_laminate', 'Laminate flooring: a printed wood decor that repeats every few planks, uniform tone, micro-bevel.',
            laminate_grain, 8, 2, 'planks', ((0.62, 0.47, 0.32), (0.5, 0.36, 0.22), (0.36, 0.24, 0.13)), 555,
            tint=0.2, lum_var=0.15, gap=0.01, bevel=0.02, rough=(0.45, 0.35))


def tongue_groove(name, desc, boards, painted, col, seed, panel=False):
    """Vertical boards (tongue-and-groove / beadboard) or a wainscot of raised panels; the grain runs
    along the boards (v)."""
    g = G(name, 'wood', desc)
    grain = wood_grain(g, rings=20, seed=seed, warp=0.02)
    g.n('gv', 'transform', {'in': grain}, rotation='90')
    if panel:
        g.n('t', 'tile', {'pattern': 'gv'}, layout='grid', rows=2, cols=boards, gap=0.06, bevel=0.25, lum_var=0.1, seed=seed)
        g.p('panel_bevel', 't.bevel', min=0.05, max=0.45)
        g.p('groove_width', 't.gap', min=0.0, max=0.1)
        prof = 't.height'
    else:
        # boards run the full height: the grooves are stripes along u (a tile row would put a
        # joint across every board at v = 0); the tile only gives each board its grain and tone
        g.n('t', 'tile', {'pattern': 'gv'}, layout='grid', rows=1, cols=boards, gap=0.0, bevel=0.005, lum_var=0.3, seed=seed)
        g.n('gr', 'stripes', count=boards, direction='u', width=0.95, softness=0.04)
        g.p('groove_width', 'gr.width', min=0.8, max=0.99)
        g.p('groove_bevel', 'gr.softness', min=0.01, max=0.1)
        prof = 'gr'
    g.p('board_variation', 't.lum_var')
    grain_scale(g, 't')
    if painted:
        tinted(g, 'paint', col[0], 'paint_color', 't.sampled', 0.9, 'grain_show_through', 0.6, sh='shade', out='c0')
        r = rough_range(g, 't.sampled', 0.55, 0.45)
    else:
        c0 = wood_colors(g, 't.sampled', *col)
        r = rough_range(g, 't.sampled', 0.5, 0.4)
        blend(g, 'c0', 't.random', c0, mode='overlay', opacity=0.4)
    shaded(g, 'c0', prof, 0.8 if panel else 0.35, 'groove_shadow', 0.0)
    g.n('h', 'blend', {'fg': 't.sampled', 'bg': prof}, mode='multiply', opacity=0.05)
    finish(g, 'h', r, 'alb', 0.006 if not panel else 0.03, normal_max=0.06 if not panel else 0.1,
           shift=(0.5 / boards, 0.25 if panel else 0))


tongue_groove('wood_tongue_groove', 'Tongue-and-groove pine boards on a wall or ceiling: narrow vertical boards, V-grooves.', 10, False,
              ((0.66, 0.46, 0.25), (0.52, 0.33, 0.15), (0.36, 0.2, 0.08)), 561)
tongue_groove('wood_beadboard_painted', 'Painted beadboard / tongue-and-groove panelling (white), grain faintly through.', 12, True,
              ([0.78, 0.78, 0.74],), 563)
tongue_groove('wood_wainscot_panels', 'Wainscot: painted raised panels in a frame (two rows), wide bevels.', 3, True,
              ([0.55, 0.62, 0.58],), 565, panel=True)


def worn_painted_planks():
    g = G('wood_painted_worn', 'wood', 'Painted floor planks with paint worn through to the wood along the edges and in traffic patches.')
    grain = wood_grain(g, rings=30, seed=571, warp=0.025, fiber=0.5)
    g.n('t', 'tile', {'pattern': grain}, layout='planks', rows=6, cols=1, row_offset=0.9, gap=0.02, bevel=0.08, lum_var=0.3, seed=572)
    g.p('plank_gap', 't.gap', min=0.0, max=0.1)
    g.p('plank_bevel', 't.bevel', min=0.01, max=0.3)
    grain_scale(g, 't')
    wood = wood_colors(g, 't.sampled', (0.5, 0.33, 0.17), (0.36, 0.21, 0.09), (0.2, 0.1, 0.04))
    uniform(g, 'paint', [0.55, 0.62, 0.66], 'paint_color')
    g.n('wn', 'fbm', scale_x=8, scale_y=8, octaves=6, roughness=0.6, seed=573)
    g.n('wm', 'blend', {'fg': 'wn', 'bg': 't.height'}, mode='multiply')
    g.n('keep', 'histogram_scan', {'in': 'wm'}, position=0.55, contrast=0.8)
    g.p('paint_left', 'keep.position', min=0.2, max=0.9)
    blend(g, 'alb0', 'paint', wood, 'keep')
    dark_joints(g, 'alb0', 't.height', [0.2, 0.17, 0.15])
    g.n('h', 'blend', {'fg': 'keep', 'bg': 't.height'}, mode='add', opacity=0.1)
    rough_range(g, 'keep', 0.75, 0.45, ('roughness_wood', 'roughness_paint'))
    finish(g, 'h', 'rough', 'alb', 0.005, normal_max=0.03, shift=(0.5, 1 / 12))


worn_painted_planks()


def wicker(name, desc, pattern, count, width, col, seed, holes=False):
    g = G(name, 'wood', desc)
    g.n('w', 'weave', count=count, pattern=pattern, width=width, seed=seed)
    g.p('strand_width', 'w.width', min=0.4 if holes else 0.7, max=1.0)
    g.n('fib', 'fbm', scale_x=count * 2, scale_y=count * 2, octaves=2, roughness=0.5, seed=seed + 1)
    blend(g, 'hf', 'fib', 'w.height', mode='overlay', opacity=0.15)
    blend(g, 'tv', 'w.random', 'hf', param='strand_variation', mode='overlay', opacity=0.4)
    alb = colors3(g, 'col', 'tv', [c * 0.45 for c in col], col, [min(1, c * 1.25) for c in col], 0.6, 'cane')
    if holes:  # cane webbing: the gaps between strands show what is behind (dark)
        g.n('hole', 'histogram_scan', {'in': 'w.height'}, position=0.8, contrast=0.9)
        g.p('hole_size', 'hole.position', min=0.5, max=1.0)
        alb = over_ground(g, 'col', 'bk', [0.03, 0.025, 0.02], 'behind_color', 'hole')
    finish(g, 'tv', rough_falling(g, 'tv', 0.55, 0.35), alb, 0.008, normal_max=0.06, shift=(0.5 / count, 0.5 / count))


wicker('wood_rattan_weave', 'Rattan / wicker furniture: thick round cane strands in a plain over-under weave.', 'plain', 12, 0.95,
       [0.58, 0.42, 0.24], 581)
wicker('wood_cane_webbing', 'Cane webbing (chair seats, cabinet doors): thin flat cane strands with open holes between them.', 'plain', 24, 0.6,
       [0.62, 0.48, 0.28], 583, holes=True)

# ---------------------------------------------------------------- stone walls and paving
def stone_wall(name, desc, scale, stone, mortar, seed, irregular=True, rows=4, cols=2):
    g = G(name, 'stone', desc)
    if irregular:
        g.n('v', 'voronoi', scale=scale, jitter=1.0, mode='f2_minus_f1', seed=seed)
        g.n('cv', 'voronoi', scale=scale, jitter=1.0, mode='cell_value', seed=seed)
        g.n('body', 'histogram_scan', {'in': 'v'}, position=0.8, contrast=0.75)
        g.p('mortar_width', 'body.position', min=0.5, max=0.98)
        g.n('bulge', 'levels', {'in': 'v'}, in_low=0.0, in_high=0.6)
        blend(g, 'hb', 'bulge', 'body', param='stone_bulge', mode='multiply', opacity=0.6)
        body, rnd, hb = 'body', 'cv', 'hb'
    else:
        g.n('t', 'tile', layout='bricks', rows=rows, cols=cols, row_offset=0.5, gap=0.06, bevel=0.2, lum_var=0.6, seed=seed)
        g.p('mortar_width', 't.gap', min=0.0, max=0.2)
        g.p('edge_rounding', 't.bevel', min=0.02, max=0.4)
        body, rnd, hb = 't.height', 't.random', 't.height'
    g.n('f', 'fbm', scale_x=8, scale_y=8, octaves=7, roughness=0.6, seed=seed + 1)
    blend(g, 'm', 'f', rnd, param='stone_texture', mode='overlay', opacity=0.6)
    colors3(g, 'col', 'm', [c * 0.55 for c in stone], stone, [min(1, c * 1.3) for c in stone], 0.5, 'stone')
    over_ground(g, 'col', 'mc', mortar, 'mortar_color', body)
    g.n('h', 'blend', {'fg': 'f', 'bg': hb}, mode='multiply', opacity=0.4)
    finish(g, 'h', rough_range(g, 'f', 0.7, 0.95), 'alb', 0.02, normal_max=0.1,
           shift=(0.5 / scale, 0.5 / scale) if irregular else (0.25 / cols, 0.5 / rows))


stone_wall('stone_rubble_wall', 'Random rubble stone wall: irregular rounded stones in deep mortar.', 6, [0.42, 0.4, 0.36], [0.55, 0.53, 0.5], 591)
stone_wall('stone_crazy_paving', 'Crazy paving: irregular flat flagstones with mortar joints.', 5, [0.5, 0.47, 0.42], [0.35, 0.34, 0.32], 593)
stone_wall('stone_ashlar_sandstone', 'Ashlar wall of dressed sandstone blocks (running bond), warm buff tones.', 0,
           [0.62, 0.5, 0.36], [0.6, 0.56, 0.5], 595, irregular=False, rows=6, cols=2)
cementish('stone_limestone', 'stone', 'Honed limestone: pale beige, fine fossil specks and soft clouding.', [0.72, 0.66, 0.55], 8, 96, (0.45, 0.6), 0.002, 597)

# ---------------------------------------------------------------- concrete, plaster
def concrete_blocks():
    g = G('concrete_block_wall', 'concrete', 'Concrete block (CMU) wall: large grey blocks in running bond, porous faces.')
    g.n('f', 'fbm', scale_x=32, scale_y=32, octaves=6, roughness=0.6, seed=601)
    pitted(g, 'f', 96, 602, 0.9, 0.8, 's')
    g.n('t', 'tile', {'pattern': 's'}, layout='bricks', rows=8, cols=2, row_offset=0.5, gap=0.05, bevel=0.04, lum_var=0.3, seed=603)
    g.p('joint_width', 't.gap', min=0.0, max=0.15)
    g.p('block_variation', 't.lum_var')
    blend(g, 'm', 't.random', 't.sampled', mode='overlay', opacity=0.4)
    colors3(g, 'col', 'm', [0.3, 0.3, 0.29], [0.45, 0.45, 0.43], [0.58, 0.58, 0.55], 0.5, 'block')
    over_ground(g, 'col', 'mc', [0.5, 0.49, 0.46], 'mortar_color', 't.height')
    g.n('h', 'blend', {'fg': 't.sampled', 'bg': 't.height'}, mode='multiply', opacity=0.3)
    finish(g, 'h', rough_range(g, 'f', 0.8, 0.95), 'alb', 0.01, shift=(0.125, 1 / 16))


concrete_blocks()


def ribbed_panels():
    # issue 18: precast facade panels with fine vertical ribs (polyhaven exterior_concrete_tile_facade,
    # the blender-room example's west wall): 2 rows of 1 panel per tile, 40 soft ribs across it (3 px
    # apart at 128 px per tile, the fit's map size: more ribs alias there), a dark grey mottled face
    # with sparse light specks
    g = G('concrete_ribbed_panels', 'concrete', 'Precast concrete facade panels with fine vertical ribs, '
          'dark grey, thin joints.')
    g.n('t', 'tile', layout='grid', rows=2, cols=1, row_offset=0.0, gap=0.015, bevel=0.015, lum_var=0.15, seed=611)
    g.p('joint_width', 't.gap', min=0.0, max=0.06)
    g.p('panel_variation', 't.lum_var')
    g.n('rib', 'stripes', count=40, direction='u', width=0.5, softness=0.35)
    g.p('rib_width', 'rib.width', min=0.2, max=0.8)
    g.n('f', 'fbm', scale_x=24, scale_y=24, octaves=6, roughness=0.6, seed=612)
    g.n('sp', 'white_noise', scale=256, seed=613)
    g.n('spk', 'histogram_scan', {'in': 'sp'}, position=0.03, contrast=0.9)
    g.p('speck_amount', 'spk.position', min=0.0, max=0.1)
    blend(g, 'face', 'f', 't.random', mode='overlay', opacity=0.5)
    blend(g, 'ribbed', 'rib', 'face', param='rib_shading', mode='multiply', opacity=0.35, min=0.0, max=0.8)
    blend(g, 'm', 'spk', 'ribbed', param='speck_strength', mode='screen', opacity=0.3)
    colors3(g, 'col', 'm', [0.035, 0.037, 0.04], [0.07, 0.072, 0.078], [0.13, 0.13, 0.135], 0.5, 'panel')
    over_ground(g, 'col', 'jc', [0.05, 0.05, 0.052], 'joint_color', 't.height')
    g.n('hr', 'blend', {'fg': 'rib', 'bg': 't.height'}, mode='multiply', opacity=0.3)
    g.p('rib_depth', 'hr.opacity', min=0.0, max=0.8)
    finish(g, 'hr', rough_range(g, 'f', 0.7, 0.85), 'alb', 0.01, shift=(0.5, 0.25))


ribbed_panels()


def hex_pavers():
    # issue 18: hexagonal concrete pavers (polyhaven hexagonal_concrete_paving). A running bond
    # whose horizontal joints are folded into chevrons is a hexagon tiling: the vertical joints
    # are the hexagons' upright sides, and each horizontal joint is moved along v by a triangle
    # wave that peaks over the centres of the row below it (its phase alternates from joint to
    # joint: two waves half a paver apart, each used in the band of rows around its joints, the
    # bands switching softly at mid-row). 4 rows of 3 pavers per tile: large pavers, width / row
    # pitch 1.33 (a regular hexagon's 1.15).
    g = G('concrete_hex_pavers', 'concrete', 'Hexagonal concrete pavers (pointy-top hexagons in '
          'offset rows) with sand joints.')
    rows, cols = 4, 3
    g.n('f', 'fbm', scale_x=16, scale_y=16, octaves=6, roughness=0.6, seed=621)
    pitted(g, 'f', 96, 622, 0.9, 0.8, 's')
    g.n('t', 'tile', {'pattern': 's'}, layout='bricks', rows=rows, cols=cols, row_offset=0.5, gap=0.08, bevel=0.1,
        lum_var=0.3, seed=623)
    g.p('joint_width', 't.gap', min=0.02, max=0.25)
    g.p('edge_chamfer', 't.bevel', min=0.02, max=0.3)
    g.p('paver_variation', 't.lum_var')
    g.n('w0', 'stripes', direction='u', count=cols, width=0.5, softness=0.5)
    g.n('w1', 'transform', {'in': 'w0'}, offset_u=0.5 / cols)
    g.n('band', 'stripes', direction='v', count=rows // 2, width=0.5, softness=0.15)
    blend(g, 'wave', 'w1', 'w0', 'band')
    blend(g, 'm', 't.random', 't.sampled', param='paver_texture', mode='overlay', opacity=0.4)
    colors3(g, 'col', 'm', [0.3, 0.29, 0.27], [0.45, 0.44, 0.41], [0.58, 0.57, 0.53], 0.5, 'paver')
    over_ground(g, 'col', 'jc', [0.25, 0.24, 0.22], 'joint_color', 't.height', out='flat')
    point = round(1 / rows / 3, 4)  # a regular hexagon's points rise a third of the row pitch
    g.n('alb', 'directional_warp', {'in': 'flat', 'height': 'wave'}, intensity=point, angle=0.25)
    g.n('h0', 'blend', {'fg': 't.sampled', 'bg': 't.height'}, mode='multiply', opacity=0.3)
    g.n('h', 'directional_warp', {'in': 'h0', 'height': 'wave'}, intensity=point, angle=0.25)
    g.p('point_height', 'alb.intensity', 'h.intensity', min=0.0, max=0.1,
        doc="how far the hexagons' points rise above and below their sides (texture units)")
    finish(g, 'h', rough_range(g, 'f', 0.8, 0.95), 'alb', 0.01)


hex_pavers()


def board_formed():
    g = G('concrete_board_formed', 'concrete', 'Board-formed concrete: the imprint of formwork boards (horizontal bands with wood grain) on grey concrete.')
    g.n('gr', 'fbm', scale_x=2, scale_y=64, octaves=4, roughness=0.6, seed=611)
    g.n('t', 'tile', {'pattern': 'gr'}, layout='planks', rows=8, cols=1, row_offset=0.9, gap=0.0, bevel=0.06, lum_var=0.4, seed=612)
    blend(g, 'imp', 't.sampled', 't.height', param='grain_imprint', mode='multiply', opacity=0.5)
    g.n('f', 'fbm', scale_x=8, scale_y=8, octaves=6, roughness=0.6, seed=613)
    blend(g, 'm', 'f', 'imp', mode='overlay', opacity=0.5)
    blend(g, 'm2', 't.random', 'm', param='board_tone_variation', mode='overlay', opacity=0.3)
    colors3(g, 'col', 'm2', [0.3, 0.3, 0.29], [0.48, 0.47, 0.45], [0.6, 0.59, 0.56], 0.5, 'concrete')
    finish(g, 'imp', rough_range(g, 'f', 0.75, 0.92), 'col', 0.006, shift=(0, 1 / 16))


board_formed()
cementish('concrete_exposed_aggregate', 'concrete', 'Exposed-aggregate / gravel concrete: dense small pebbles in a coarse grey matrix.', [0.45, 0.43, 0.4], 48, 128, (0.8, 0.95), 0.015, 621)
cementish('plaster_lime_rough', 'plaster', 'Rough lime plaster: coarse sand-float finish, warm white, uneven.', [0.78, 0.74, 0.66], 48, 128, (0.85, 0.97), 0.012, 631)
cementish('plaster_painted_red', 'plaster', 'Painted plaster wall in a strong colour, with trowel clouding and filled pores.', [0.5, 0.12, 0.08], 4, 48, (0.7, 0.85), 0.004, 633)

# ---------------------------------------------------------------- wallpaper motifs
def wallpaper_motif(name, desc, kind, col_a, col_b, seed):
    g = G(name, 'wallpaper', desc)
    if kind == 'dots':
        staggered_discs(g, ('m1', 'm2', 'mot'), 8, 0.35, 0.04, 1 / 16)
        g.p('dot_size', 'm1.size', min=0.1, max=0.7)
    elif kind == 'trellis':  # an ogee-like trellis: diagonal lines bent by a radial field
        diagonals(g, ('d1', 'd2'), 6, 0.12, 0.03)
        g.n('dd', 'blend', {'fg': 'd1', 'bg': 'd2'}, mode='max')
        g.n('rad', 'gradient_radial', count=6, radius=1.0)
        g.n('mot', 'warp', {'in': 'dd', 'height': 'rad'}, intensity=0.001)
        g.p('line_width', 'd1.width', 'd2.width', min=0.02, max=0.3)
        g.p('curvature', 'mot.intensity', min=0.0, max=0.003)
    elif kind == 'floral':  # four petals round a centre, half-drop repeat
        petals = []
        for i, (du, dv) in enumerate([(0.03, 0), (-0.03, 0), (0, 0.03), (0, -0.03)]):
            petals.append(g.n('p%d' % i, 'transform', {'in': 'pet'}, offset_u=du, offset_v=dv))
        g.n('pet', 'shape', count=4, shape='bell', size=0.28)
        g.p('petal_size', 'pet.size', min=0.1, max=0.5)
        g.n('f1', 'blend', {'fg': petals[0], 'bg': petals[1]}, mode='max')
        g.n('f2', 'blend', {'fg': petals[2], 'bg': petals[3]}, mode='max')
        g.n('fl', 'blend', {'fg': 'f1', 'bg': 'f2'}, mode='max')
        g.n('fh', 'transform', {'in': 'fl'}, offset_u=0.125, offset_v=0.125)
        g.n('fl2', 'blend', {'fg': 'fh', 'bg': 'fl'}, mode='max')
        g.n('mot', 'histogram_scan', {'in': 'fl2'}, position=0.5, contrast=0.8)
        g.p('bloom', 'mot.position', min=0.2, max=0.8)
    else:  # geometric: interlocking diamonds and squares
        triangle_waves(g, 6)
        g.n('dia', 'blend', {'fg': 'tu', 'bg': 'tv'}, mode='copy', opacity=0.5)
        g.n('ring', 'histogram_scan', {'in': 'dia'}, position=0.5, contrast=0.9)
        g.n('ring2', 'histogram_scan', {'in': 'dia'}, position=0.35, contrast=0.9)
        g.n('ir', 'invert', {'in': 'ring2'})
        g.n('mot', 'blend', {'fg': 'ir', 'bg': 'ring'}, mode='multiply')
        g.p('band_outer', 'ring.position', min=0.3, max=0.8)
        g.p('band_inner', 'ring2.position', min=0.05, max=0.45)
    two_tone(g, 'm', 'mot', (col_a, col_b), ('ground_color', 'motif_color'))
    paper_texture(g, 'm', seed, 0.12)
    g.n('h', 'blend', {'fg': 'mot', 'bg': 'paper'}, mode='add', opacity=0.2)
    rough_range(g, 'mot', 0.8, 0.55, ('roughness_ground', 'roughness_motif'))
    finish(g, 'h', 'rough', 'alb', 0.003)


wallpaper_motif('wallpaper_polka_dots', 'Polka-dot wallpaper: dots in a diagonal (half-drop) grid.', 'dots', [0.8, 0.78, 0.72], [0.2, 0.3, 0.45], 641)
wallpaper_motif('wallpaper_trellis', 'Trellis / ogee wallpaper: a lattice of curved diagonal lines.', 'trellis', [0.45, 0.55, 0.5], [0.85, 0.83, 0.76], 643)
wallpaper_motif('wallpaper_floral', 'Floral wallpaper: four-petal flowers in a half-drop repeat on a pale ground.', 'floral', [0.78, 0.74, 0.62], [0.55, 0.2, 0.25], 645)
wallpaper_motif('wallpaper_geometric', 'Geometric wallpaper: nested diamond bands in a regular lattice.', 'geometric', [0.12, 0.14, 0.18], [0.7, 0.6, 0.35], 647)

# ---------------------------------------------------------------- metal, plastic
def perforated_metal():
    g = G('metal_perforated', 'metal', 'Perforated metal sheet: round holes in a staggered grid, dark behind.')
    staggered_discs(g, ('h1', 'h2', 'holes'), 16, 0.55, 0.06, 1 / 32)
    g.p('hole_size', 'h1.size', min=0.2, max=0.9)
    g.n('sheet', 'invert', {'in': 'holes'})
    g.n('br', 'fbm', scale_x=2, scale_y=256, octaves=3, roughness=0.6, seed=651)
    colors3(g, 'col', 'br', [0.45, 0.45, 0.47], [0.58, 0.58, 0.6], [0.68, 0.68, 0.7], 0.5, 'metal')
    over_ground(g, 'col', 'bk', [0.02, 0.02, 0.02], 'behind_color', 'sheet')
    rough_range(g, 'br', 0.3, 0.45)
    finish(g, 'sheet', 'rough', 'alb', 0.004, metallic=metallic_where(g, 'sheet', 1.0, 'sheet_metallic'))


perforated_metal()


def tread_plate():
    g = G('metal_tread_plate', 'metal', 'Diamond (tread) plate: raised short bars alternating in direction on steel / '
          'aluminium, mottled in brightness only (one colour: a free three-colour ramp drifted to red, yellow and '
          'purple blotches when fitted to worn plates).')
    diagonals(g, ('d1', 'd2'), 24, 0.3, 0.3)
    g.n('sel', 'checker', count=6, softness=0.01)
    blend(g, 'bars', 'd1', 'd2', 'sel')
    g.n('cell', 'shape', count=12, shape='bell', size=0.8)
    g.n('h', 'blend', {'fg': 'cell', 'bg': 'bars'}, mode='multiply')
    g.n('br', 'fbm', scale_x=4, scale_y=4, octaves=4, roughness=0.5, seed=661)
    g.n('metal_base', 'uniform_color', color=[0.62, 0.62, 0.64])
    g.p('metal_color', 'metal_base.color', doc="the plate's mean colour (linear RGB); its mottling varies only its "
        'brightness, so the fit cannot paint it in several hues')
    g.n('shade', 'levels', {'in': 'br'}, in_low=0.2, in_high=0.8, out_low=0.75, out_high=1.15)
    g.p('mottle_dark', 'shade.out_low', doc='brightness of the darkest mottling relative to metal_color', min=0.3, max=1.0)
    g.p('mottle_light', 'shade.out_high', doc='brightness of the lightest mottling relative to metal_color', min=1.0,
        max=1.5)
    g.n('mottled', 'blend', {'fg': 'shade', 'bg': 'metal_base'}, mode='multiply')
    g.n('bar_shade', 'levels', {'in': 'h'}, out_low=0.85, out_high=1.0)
    g.p('groove_brightness', 'bar_shade.out_low', doc='albedo between the bars relative to on them (1: the same)',
        min=0.4, max=1.0)
    g.n('col', 'blend', {'fg': 'bar_shade', 'bg': 'mottled'}, mode='multiply')
    rough_range(g, 'br', 0.25, 0.45)
    finish(g, 'h', 'rough', 'col', 0.01, metallic=fully_metallic(g), shift=(1 / 48, 1 / 48))


tread_plate()


def panels_weathered():
    g = G('metal_panels_weathered', 'metal',
          'Weathered metal sheet in panels (cladding, plates, a cabinet side): a painted or bare base with broad '
          'stains and vertical run-off streaks, darker seams between the panels, and rust spreading from the seams in '
          'rust colours (hue and lightness vary within a narrow band, so the fit cannot turn it purple). Closes the '
          'rusted and stained plates of the coverage set (modules/graph/README.md).')
    g.n('panels', 'tile', layout='grid', rows=4, cols=2, gap=0.015, bevel=0.02, lum_var=0.15, seed=801)
    g.n('base', 'uniform_color', color=[0.42, 0.43, 0.45])
    g.p('base_color', 'base.color', doc='paint or bare metal colour (linear RGB)')
    g.n('stain_noise', 'fbm', scale_x=4, scale_y=4, octaves=6, roughness=0.6, seed=802)
    g.n('stain', 'levels', {'in': 'stain_noise'}, in_low=0.2, in_high=0.8, out_low=0.75, out_high=1.0)
    g.p('stain_floor', 'stain.out_low', doc='brightness of the darkest stains (1: none)', min=0.3, max=1.0)
    g.n('streak_noise', 'fbm', scale_x=24, scale_y=2, octaves=4, roughness=0.5, seed=803)
    g.n('streak', 'levels', {'in': 'streak_noise'}, in_low=0.3, in_high=0.7, out_low=0.8, out_high=1.0)
    g.p('streak_floor', 'streak.out_low', doc='brightness of the darkest run-off streaks (1: none)', min=0.4, max=1.0)
    g.n('stained', 'blend', {'fg': 'stain', 'bg': 'base'}, mode='multiply')
    g.n('streaked', 'blend', {'fg': 'streak', 'bg': 'stained'}, mode='multiply')
    g.n('varied', 'blend', {'fg': 'panels.random', 'bg': 'streaked'}, mode='overlay')
    g.p('panel_variation', 'panels.lum_var', doc='per-panel shade spread', min=0.0, max=0.6)
    g.n('seam', 'levels', {'in': 'panels.height'}, out_low=0.5, out_high=1.0)
    g.p('seam_darkness', 'seam.out_low', doc='brightness in the seams (1: invisible seams)', min=0.0, max=1.0)
    g.p('panel_rows', 'panels.rows', doc='panel rows per texture', min=1, max=8)
    g.p('panel_cols', 'panels.cols', doc='panels per row per texture', min=1, max=8)
    g.n('paint', 'blend', {'fg': 'seam', 'bg': 'varied'}, mode='multiply')
    # rust: a noise field raised along the seams, thresholded; its colours a fixed rust ramp that
    # only shifts a little in hue and lightness
    g.n('rust_noise', 'fbm', scale_x=8, scale_y=3, octaves=7, roughness=0.65, seed=804)
    g.n('gap', 'invert', {'in': 'panels.height'})
    g.n('rust_field', 'blend', {'fg': 'gap', 'bg': 'rust_noise'}, mode='add', opacity=0.3)
    g.n('rust_mask', 'histogram_scan', {'in': 'rust_field'}, position=0.2, contrast=0.7)
    g.p('rust_amount', 'rust_mask.position', doc='share of the surface rusted (0: none)', min=0.0, max=0.9)
    g.n('rust_grain', 'fbm', scale_x=24, scale_y=24, octaves=4, roughness=0.55, seed=805)
    g.n('rust_ramp', 'gradient_map', {'in': 'rust_grain'}, color_0=[0.10, 0.04, 0.02], color_1=[0.33, 0.13, 0.05],
        color_2=[0.55, 0.30, 0.12], position=0.5)
    g.n('rust', 'hsl', {'in': 'rust_ramp'}, hue=0.0, saturation=1.0, lightness=0.0)
    g.p('rust_hue', 'rust.hue', doc='hue shift of the rust colours (turns; a narrow band around orange-brown)',
        min=-0.04, max=0.04)
    g.p('rust_lightness', 'rust.lightness', doc='added to the rust colours', min=-0.1, max=0.2)
    blend(g, 'alb', 'rust', 'paint', 'rust_mask')
    rough_range(g, 'rust_mask', 0.4, 0.8, names=('roughness_paint', 'roughness_rust'))
    g.n('bare', 'invert', {'in': 'rust_mask'})
    g.n('metal', 'levels', {'in': 'bare'}, out_low=0.0, out_high=0.3)
    g.p('metallic', 'metal.out_high', doc='metalness of the unrusted surface (0: painted)')
    g.n('h', 'blend', {'fg': 'rust_noise', 'bg': 'panels.height'}, mode='copy', opacity=0.25)
    finish(g, 'h', 'rough', 'alb', 0.005, metallic='metal', normal_max=0.03, shift=(1 / 64, 1 / 64))


panels_weathered()


def woven_vinyl():
    g = G('plastic_woven_vinyl', 'plastic', 'Woven vinyl flooring: flat two-colour PVC strands in a basket weave, semi-gloss.')
    g.n('w', 'weave', count=48, pattern='basket_2_2', width=0.92, seed=671)
    g.p('strand_width', 'w.width', min=0.7, max=1.0)
    warp_weft_colors(g, [0.3, 0.3, 0.28], [0.55, 0.53, 0.48], 'w.warp')
    g.n('fl', 'levels', {'in': 'w.height'}, in_low=0.3, in_high=0.9)
    shaded(g, 'cm', 'fl', 0.6, 'shadowing', 0.2)
    finish(g, 'fl', rough_falling(g, 'fl', 0.6, 0.35), 'alb', 0.003)


woven_vinyl()


if __name__ == '__main__':
    os.makedirs(OUT, exist_ok=True)
    names = set()
    for g in GRAPHS:
        assert g.name not in names, g.name
        names.add(g.name)
        with open(os.path.join(OUT, g.name + '.json'), 'w') as f:
            json.dump(g.json(), f, indent=1)
            f.write('\n')
    print(len(GRAPHS), 'graphs written to', os.path.normpath(OUT))
