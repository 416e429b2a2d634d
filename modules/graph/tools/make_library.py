#!/usr/bin/env python3
"""Writes the graph library (modules/graph/library/*.json) from compact Python descriptions.

The JSON files are the data the engine reads (format: ../FORMAT.md); this script is only a
convenience for maintainers. Users add graphs by writing JSON directly.
Run: python3 modules/graph/tools/make_library.py
"""
import json, os

OUT = os.path.join(os.path.dirname(__file__), '..', 'library')
GRAPHS = []


class G:
    def __init__(self, name, category, description):
        self.name, self.category, self.description = name, category, description
        self.nodes, self.params, self.outputs = [], [], {}

    def n(self, id, type, inputs=None, **params):
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
        GRAPHS.append(self)

    def json(self):
        return {'name': self.name, 'category': self.category, 'description': self.description,
                'nodes': self.nodes, 'parameters': self.params, 'outputs': self.outputs}


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
    if normal_max is None:
        normal_max = round(min(0.1, max(0.02, 10 * normal_intensity)), 4)
    g.n('nrm', 'normal', {'height': height}, intensity=normal_intensity)
    g.p('normal_strength', 'nrm.intensity', doc='relief strength', min=0.0, max=normal_max)
    g.out(albedo=albedo, normal='nrm', roughness=rough, height=height)
    if metallic:
        g.out(metallic=metallic)
    g.done()


def rough_from(g, src, lo, hi, id='rough'):
    g.n(id, 'levels', {'in': src}, out_low=lo, out_high=hi)
    g.p('roughness_min', id + '.out_low', min=0.0, max=1.0)
    g.p('roughness_max', id + '.out_high', min=0.0, max=1.0)
    return id


def colors3(g, id, src, c0, c1, c2, pos=0.5, prefix='color'):
    g.n(id, 'gradient_map', {'in': src}, color_0=c0, color_1=c1, color_2=c2, position=pos)
    g.p(prefix + '_dark', id + '.color_0', doc='ramp color at 0')
    g.p(prefix + '_mid', id + '.color_1', doc='ramp color at the midpoint')
    g.p(prefix + '_light', id + '.color_2', doc='ramp color at 1')
    return id


# ---------------------------------------------------------------- wood
def wood_grain(g, rings=36, seed=1, warp=0.025, fiber=0.35):
    """Gray grain along u: soft stripes across v, gently wavy (long waves), with fine fibers."""
    g.n('ring', 'stripes', count=rings, direction='v', width=0.35, softness=0.35)
    g.n('wave', 'fbm', scale_x=1, scale_y=2, octaves=3, roughness=0.35, seed=seed)
    g.n('wavy', 'directional_warp', {'in': 'ring', 'height': 'wave'}, intensity=warp, angle=0.25)
    g.n('fib', 'fbm', scale_x=4, scale_y=96, octaves=3, roughness=0.6, seed=seed + 7)
    g.n('grain', 'blend', {'fg': 'fib', 'bg': 'wavy'}, mode='overlay', opacity=fiber)
    g.p('ring_waviness', 'wavy.intensity', min=0.0, max=0.05)
    g.p('ring_width', 'ring.width', min=0.1, max=0.8)
    g.p('fiber_strength', 'grain.opacity', min=0.0, max=1.0)
    return 'grain'


def wood_colors(g, src, light=(0.45, 0.26, 0.12), mid=(0.30, 0.15, 0.06), dark=(0.16, 0.07, 0.025)):
    return colors3(g, 'wcol', src, list(dark), list(mid), list(light), 0.5, 'wood')


def wood_planks(name, rows, cols, layout, col, seed, desc):
    g = G(name, 'wood', desc)
    grain = wood_grain(g, seed=seed)
    g.n('tiles', 'tile', {'pattern': grain}, layout=layout, rows=rows, cols=cols, row_offset=0.5 if layout == 'bricks' else 0.9,
        gap=0.02, bevel=0.03, lum_var=0.5, seed=seed)
    g.p('plank_gap', 'tiles.gap', min=0.0, max=0.1)
    g.p('plank_bevel', 'tiles.bevel', min=0.005, max=0.2)
    g.p('plank_rows', 'tiles.rows', min=2, max=24)
    g.p('row_offset', 'tiles.row_offset')
    g.p('plank_variation', 'tiles.lum_var')
    c = wood_colors(g, 'tiles.sampled', *col)
    g.n('tint', 'blend', {'fg': 'tiles.random', 'bg': c}, mode='overlay', opacity=0.5)
    g.p('plank_tint', 'tint.opacity', doc='per-plank brightness variation')
    g.n('gap_dark', 'blend', {'fg': 'gapc', 'bg': 'tint', 'mask': 'gapm'}, mode='multiply', opacity=1.0)
    g.n('gapm', 'invert', {'in': 'tiles.height'})
    g.n('gapc', 'uniform_color', color=[0.25, 0.2, 0.17])
    g.n('h', 'blend', {'fg': grain, 'bg': 'tiles.height'}, mode='multiply', opacity=0.15)
    r = rough_from(g, grain, 0.5, 0.38)
    # the roughness follows the unsampled grain (no joints): only albedo and height move; along u
    # only the running bond needs it (`planks` rows have random offsets, so a plank end lies on
    # the border no more often than on any other column; moving them also made the optim test's
    # UV-rotation recovery on wood_planks land 34 degrees off)
    finish(g, 'h', r, 'gap_dark', 0.005, normal_max=0.03, shift=(0.25 / cols if layout == 'bricks' else 0.0, 0.5 / rows),
           shift_maps=('alb', 'hgt'))


wood_planks('wood_planks', 8, 2, 'planks', ((0.50, 0.30, 0.14), (0.34, 0.18, 0.07), (0.18, 0.08, 0.03)), 1,
            'Oak-like floor planks with random row offsets, grain following each plank.')
wood_planks('wood_planks_dark', 6, 1, 'planks', ((0.20, 0.10, 0.05), (0.12, 0.06, 0.03), (0.06, 0.03, 0.015)), 5,
            'Dark walnut-like wide planks.')
wood_planks('wood_planks_light', 10, 3, 'bricks', ((0.70, 0.52, 0.32), (0.58, 0.40, 0.22), (0.40, 0.26, 0.12)), 9,
            'Light maple/pine planks in a regular running bond.')


def parquet_herringbone():
    g = G('wood_parquet_herringbone', 'wood', 'Herringbone parquet; the grain turns with every plank.')
    grain = wood_grain(g, rings=48, seed=3, warp=0.015)
    g.n('hb', 'herringbone', {'pattern': grain}, count=2, ratio=4, gap=0.04, bevel=0.06, lum_var=0.6, seed=4)
    g.p('plank_ratio', 'hb.ratio')
    g.p('repeats', 'hb.count', min=1, max=6)
    g.p('plank_gap', 'hb.gap', min=0.0, max=0.2)
    g.p('plank_bevel', 'hb.bevel', min=0.005, max=0.3)
    c = wood_colors(g, 'hb.sampled', (0.52, 0.32, 0.15), (0.36, 0.19, 0.08), (0.2, 0.09, 0.035))
    g.n('tint', 'blend', {'fg': 'hb.random', 'bg': c}, mode='overlay', opacity=0.5)
    g.p('plank_tint', 'tint.opacity')
    g.n('gapm', 'invert', {'in': 'hb.height'})
    g.n('gapc', 'uniform_color', color=[0.3, 0.25, 0.2])
    g.n('alb', 'blend', {'fg': 'gapc', 'bg': 'tint', 'mask': 'gapm'}, mode='multiply')
    g.n('h', 'blend', {'fg': grain, 'bg': 'hb.height'}, mode='multiply', opacity=0.15)
    r = rough_from(g, grain, 0.45, 0.35)
    finish(g, 'h', r, 'alb', 0.005, normal_max=0.03, shift=(1 / 64, 3 / 64))


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
    g.n('tint', 'blend', {'fg': 'tiles.random', 'bg': c}, mode='overlay', opacity=0.4)
    g.p('block_tint', 'tint.opacity')
    g.n('h', 'blend', {'fg': grain, 'bg': 'tiles.height'}, mode='multiply', opacity=0.15)
    r = rough_from(g, grain, 0.45, 0.35)
    finish(g, 'h', r, 'tint', 0.005, normal_max=0.03, shift=(1 / 12, 1 / 12))


parquet_grid()


def veneer():
    g = G('wood_veneer', 'wood', 'Continuous wood veneer (furniture, doors): flowing grain, satin finish.')
    grain = wood_grain(g, rings=20, seed=21, warp=0.04, fiber=0.3)
    c = wood_colors(g, grain, (0.62, 0.40, 0.20), (0.46, 0.26, 0.11), (0.28, 0.13, 0.05))
    g.n('hsl', 'hsl', {'in': c})
    g.p('hue_shift', 'hsl.hue', min=-0.01, max=0.01)
    g.p('saturation', 'hsl.saturation', min=0.85, max=1.2)
    r = rough_from(g, grain, 0.35, 0.25)
    g.n('h', 'levels', {'in': grain}, out_low=0.4, out_high=0.6)
    finish(g, 'h', r, 'hsl', 0.005)


veneer()


def painted_wood():
    g = G('wood_painted', 'wood', 'Painted wooden boards: paint color over faint grain and plank seams.')
    grain = wood_grain(g, rings=30, seed=31, warp=0.025, fiber=0.5)
    g.n('tiles', 'tile', {'pattern': grain}, layout='bricks', rows=2, cols=6, gap=0.005, bevel=0.01, lum_var=0.1, seed=32)
    g.p('board_count', 'tiles.cols', min=2, max=16)
    g.p('board_gap', 'tiles.gap', min=0.0, max=0.05)
    g.n('rot', 'transform', {'in': 'tiles.sampled'}, rotation='90')
    g.n('paint', 'uniform_color', color=[0.70, 0.69, 0.64])
    g.p('paint_color', 'paint.color')
    g.n('shade', 'levels', {'in': 'rot'}, out_low=0.85, out_high=1.0)
    g.p('grain_show_through', 'shade.out_low', min=0.5, max=1.0)
    g.n('alb0', 'blend', {'fg': 'shade', 'bg': 'paint'}, mode='multiply')
    # the board layout turns with the grain (horizontal boards, grain along them)
    g.n('roth', 'transform', {'in': 'tiles.height'}, rotation='90')
    g.n('gapm', 'invert', {'in': 'roth'})
    g.n('alb', 'blend', {'fg': 'gapm', 'bg': 'alb0'}, mode='subtract', opacity=0.5)
    g.n('h', 'blend', {'fg': 'rot', 'bg': 'roth'}, mode='multiply', opacity=0.1)
    r = rough_from(g, 'rot', 0.45, 0.3)
    g.n('rj', 'blend', {'fg': 'gapm', 'bg': r}, mode='add', opacity=0.3)
    finish(g, 'h', 'rj', 'alb', 0.005, normal_max=0.03, shift=(0.25, 1 / 24))


painted_wood()

# ---------------------------------------------------------------- tiles
def tile_graph(name, desc, layout, rows, cols, tile_col, grout_col, gap, bevel, var, rough=(0.12, 0.2), noise_scale=4,
               category='tile', shape_mask=None):
    g = G(name, category, desc)
    g.n('t', 'tile', layout=layout, rows=rows, cols=cols, row_offset=0.5, gap=gap, bevel=bevel, lum_var=var, seed=3)
    g.p('rows', 't.rows', min=max(1, rows // 3), max=rows * 3)
    g.p('cols', 't.cols', min=max(1, cols // 3), max=cols * 3)
    g.p('grout_width', 't.gap', min=0.0, max=0.3)
    g.p('bevel', 't.bevel', min=0.005, max=0.3)
    g.p('tile_variation', 't.lum_var')
    g.n('cloud', 'fbm', scale_x=noise_scale, scale_y=noise_scale, octaves=5, roughness=0.5, seed=5)
    g.n('var', 'blend', {'fg': 'cloud', 'bg': 't.random'}, mode='overlay', opacity=0.3)
    g.p('surface_mottling', 'var.opacity')
    g.n('tc', 'gradient_map', {'in': 'var'}, color_0=[c * 0.8 for c in tile_col], color_1=tile_col,
        color_2=[min(1.0, c * 1.15) for c in tile_col], position=0.5)
    g.p('tile_color', 'tc.color_1')
    g.p('tile_color_dark', 'tc.color_0')
    g.n('gc', 'uniform_color', color=grout_col)
    g.p('grout_color', 'gc.color')
    g.n('alb', 'blend', {'fg': 'tc', 'bg': 'gc', 'mask': 't.height'})
    g.n('gn', 'fbm', scale_x=32, scale_y=32, octaves=3, roughness=0.5, seed=9)
    g.n('h', 'blend', {'fg': 'gn', 'bg': 't.height'}, mode='multiply', opacity=0.05)
    g.n('rm', 'blend', {'fg': 't.height', 'bg': 'gn'}, mode='copy', opacity=0.9)
    g.n('rough', 'levels', {'in': 'rm'}, out_low=0.8, out_high=rough[0])
    g.p('roughness_grout', 'rough.out_low')
    g.p('roughness_tile', 'rough.out_high')
    finish(g, 'h', 'rough', 'alb', 0.01, shift=((0.25 if layout == 'bricks' else 0.5) / cols, 0.5 / rows))


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


def checker_tiles():
    g = G('tile_checker', 'tile', 'Black and white checker floor tiles (two colours alternating, thin grout).')
    g.n('t', 'tile', layout='grid', rows=8, cols=8, row_offset=0.0, gap=0.03, bevel=0.04, lum_var=0.05, seed=3)
    # the checker node's count is periods of 2 x 2 squares: count 4 gives the 8 x 8 squares of
    # the 8 x 8 tiles (one colour per tile)
    g.n('chk', 'checker', count=4, softness=0.002)
    g.p('grout_width', 't.gap', min=0.0, max=0.2)
    g.p('bevel', 't.bevel', min=0.005, max=0.3)
    g.p('tile_variation', 't.lum_var')
    g.n('cloud', 'fbm', scale_x=4, scale_y=4, octaves=5, roughness=0.5, seed=5)
    g.n('var', 'blend', {'fg': 'cloud', 'bg': 't.random'}, mode='overlay', opacity=0.2)
    g.p('surface_mottling', 'var.opacity')
    g.n('ca', 'gradient_map', {'in': 'var'}, color_0=[0.62, 0.62, 0.6], color_1=[0.75, 0.75, 0.73], color_2=[0.82, 0.82, 0.8])
    g.p('light_tile_color', 'ca.color_1')
    g.n('cb', 'gradient_map', {'in': 'var'}, color_0=[0.012, 0.012, 0.013], color_1=[0.025, 0.025, 0.027], color_2=[0.04, 0.04, 0.042])
    g.p('dark_tile_color', 'cb.color_1')
    g.n('tc', 'blend', {'fg': 'ca', 'bg': 'cb', 'mask': 'chk'})
    g.n('gc', 'uniform_color', color=[0.45, 0.44, 0.42])
    g.p('grout_color', 'gc.color')
    g.n('alb', 'blend', {'fg': 'tc', 'bg': 'gc', 'mask': 't.height'})
    g.n('gn', 'fbm', scale_x=32, scale_y=32, octaves=3, roughness=0.5, seed=9)
    g.n('h', 'blend', {'fg': 'gn', 'bg': 't.height'}, mode='multiply', opacity=0.05)
    g.n('rm', 'blend', {'fg': 't.height', 'bg': 'gn'}, mode='copy', opacity=0.9)
    g.n('rough', 'levels', {'in': 'rm'}, out_low=0.8, out_high=0.12)
    g.p('roughness_grout', 'rough.out_low')
    g.p('roughness_tile', 'rough.out_high')
    finish(g, 'h', 'rough', 'alb', 0.01, shift=(1 / 16, 1 / 16))


checker_tiles()


def hex_tiles():
    g = G('tile_hexagon', 'tile', 'Hexagon-like penny mosaic: discs of glazed tile in grout (offset rows).')
    g.n('d1', 'shape', count=12, shape='disc', size=0.9, softness=0.06)
    g.n('d2', 'transform', {'in': 'd1'}, offset_u=0.0416667, offset_v=0.0416667)
    g.n('d', 'blend', {'fg': 'd1', 'bg': 'd2'}, mode='max')
    g.p('tile_size', 'd1.size', min=0.5, max=1.0)
    g.p('edge_softness', 'd1.softness', min=0.02, max=0.2)
    g.n('rnd', 'white_noise', scale=24, seed=4)
    g.n('tc', 'gradient_map', {'in': 'rnd'}, color_0=[0.75, 0.75, 0.72], color_1=[0.8, 0.8, 0.78], color_2=[0.9, 0.9, 0.88])
    g.p('tile_color_a', 'tc.color_0')
    g.p('tile_color_b', 'tc.color_2')
    g.n('gc', 'uniform_color', color=[0.3, 0.3, 0.3])
    g.p('grout_color', 'gc.color')
    g.n('alb', 'blend', {'fg': 'tc', 'bg': 'gc', 'mask': 'd'})
    g.n('rough', 'levels', {'in': 'd'}, out_low=0.8, out_high=0.1)
    g.p('roughness_grout', 'rough.out_low')
    g.p('roughness_tile', 'rough.out_high')
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
    g.n('cl', 'blend', {'fg': 'f', 'bg': 'veins'}, mode='screen', opacity=0.3)
    g.p('clouding', 'cl.opacity')
    g.n('col', 'gradient_map', {'in': 'cl'}, color_0=base, color_1=[(a + b) / 2 for a, b in zip(base, vein)], color_2=vein, position=0.6)
    g.p('stone_color', 'col.color_0')
    g.p('vein_color', 'col.color_2')
    g.n('rough', 'levels', {'in': 'veins'}, out_low=0.08, out_high=0.15)
    g.p('roughness_base', 'rough.out_low')
    g.p('roughness_veins', 'rough.out_high')
    finish(g, 'veins', 'rough', 'col', 0.001)


marble('stone_marble_white', 'White Carrara-like polished marble with grey veins.', [0.82, 0.82, 0.8], [0.35, 0.36, 0.38], 41)
marble('stone_marble_dark', 'Dark polished marble (Nero Marquina-like) with white veins.', [0.04, 0.04, 0.045], [0.75, 0.75, 0.73], 43)


def granite(name, desc, c0, c1, c2, seed, cat='stone', rough=(0.15, 0.3), scale=64):
    g = G(name, cat, desc)
    g.n('v', 'voronoi', scale=scale, jitter=1.0, mode='cell_value', seed=seed)
    g.n('f', 'fbm', scale_x=8, scale_y=8, octaves=5, roughness=0.6, seed=seed + 1)
    g.n('m', 'blend', {'fg': 'f', 'bg': 'v'}, mode='overlay', opacity=0.5)
    g.p('cloudiness', 'm.opacity')
    g.n('hs', 'histogram_scan', {'in': 'm'}, position=0.5, contrast=0.3)
    g.p('speckle_amount', 'hs.position', min=0.2, max=0.8)
    g.p('speckle_contrast', 'hs.contrast', min=0.0, max=0.9)
    colors3(g, 'col', 'hs', c0, c1, c2, 0.5, 'stone')
    g.n('rough', 'levels', {'in': 'hs'}, out_low=rough[0], out_high=rough[1])
    g.p('roughness_min', 'rough.out_low')
    g.p('roughness_max', 'rough.out_high')
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
    g.p('chip_color_a', 'cc.color_0')
    g.p('chip_color_b', 'cc.color_1')
    g.p('chip_color_c', 'cc.color_2')
    g.n('f', 'fbm', scale_x=16, scale_y=16, octaves=4, roughness=0.5, seed=62)
    g.n('mc', 'gradient_map', {'in': 'f'}, color_0=[0.72, 0.7, 0.66], color_1=[0.78, 0.76, 0.72], color_2=[0.84, 0.82, 0.78])
    g.p('matrix_color', 'mc.color_1')
    g.n('alb', 'blend', {'fg': 'cc', 'bg': 'mc', 'mask': 'chips'})
    g.n('rough', 'levels', {'in': 'chips'}, out_low=0.3, out_high=0.2)
    g.p('roughness_matrix', 'rough.out_low')
    g.p('roughness_chips', 'rough.out_high')
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
    g.n('pc', 'uniform_color', color=[0.45, 0.37, 0.27])
    g.n('alb0', 'blend', {'fg': 'pc', 'bg': 'col', 'mask': 'pitm'}, opacity=0.7)
    g.n('alb', 'blend', {'fg': 't.random', 'bg': 'alb0'}, mode='overlay', opacity=0.2)
    g.n('h0', 'blend', {'fg': 'pitm', 'bg': 't.height'}, mode='subtract', opacity=0.5)
    g.n('rough', 'levels', {'in': 'band'}, out_low=0.45, out_high=0.6)
    g.p('roughness_min', 'rough.out_low')
    g.p('roughness_max', 'rough.out_high')
    finish(g, 'h0', 'rough', 'alb', 0.005, shift=(0.125, 0.125))


travertine()


def slate():
    g = G('stone_slate', 'stone', 'Cleft slate flagstones: dark grey layered stone in a grid.')
    g.n('f', 'fbm', scale_x=4, scale_y=4, octaves=7, roughness=0.6, seed=81)
    g.n('t', 'tile', {'pattern': 'f'}, layout='bricks', rows=3, cols=2, gap=0.03, bevel=0.05, lum_var=0.5, seed=82)
    g.p('rows', 't.rows', min=2, max=8)
    g.p('gap', 't.gap', min=0.0, max=0.1)
    g.p('variation', 't.lum_var')
    g.n('cl', 'blend', {'fg': 't.random', 'bg': 't.sampled'}, mode='overlay', opacity=0.5)
    colors3(g, 'col', 'cl', [0.06, 0.065, 0.07], [0.16, 0.17, 0.18], [0.3, 0.3, 0.3])
    g.n('gc', 'uniform_color', color=[0.25, 0.24, 0.23])
    g.n('alb', 'blend', {'fg': 'col', 'bg': 'gc', 'mask': 't.height'})
    g.n('h', 'blend', {'fg': 't.sampled', 'bg': 't.height'}, mode='multiply', opacity=0.6)
    # roughness: the flag's own (shifted) cleft pattern on the stone, the grout's value in the
    # joints; every flag samples the pattern at another offset, so the mask keeps the change of
    # pattern inside the joint instead of a roughness step along every flag border
    g.n('rs', 'levels', {'in': 't.sampled'}, out_low=0.5, out_high=0.8)
    g.p('roughness_min', 'rs.out_low')
    g.p('roughness_max', 'rs.out_high')
    g.n('rg', 'uniform_gray', value=0.9)
    g.p('roughness_grout', 'rg.value')
    g.n('rough', 'blend', {'fg': 'rs', 'bg': 'rg', 'mask': 't.height'})
    finish(g, 'h', 'rough', 'alb', 0.01, shift=(0.125, 0.125))


slate()

# ---------------------------------------------------------------- concrete / plaster / paint
def cementish(name, cat, desc, c, scale, pores, rough, relief, seed):
    g = G(name, cat, desc)
    g.n('f', 'fbm', scale_x=scale, scale_y=scale, octaves=7, roughness=0.6, seed=seed)
    g.n('big', 'fbm', scale_x=2, scale_y=2, octaves=3, roughness=0.5, seed=seed + 1)
    g.n('m', 'blend', {'fg': 'big', 'bg': 'f'}, mode='overlay', opacity=0.6)
    g.p('stain_amount', 'm.opacity')
    g.n('p', 'voronoi', scale=pores, jitter=1.0, mode='f1', seed=seed + 2)
    g.n('pm', 'histogram_scan', {'in': 'p'}, position=0.93, contrast=0.7)
    g.p('pore_amount', 'pm.position', min=0.85, max=1.0)
    g.n('mm', 'blend', {'fg': 'pm', 'bg': 'm'}, mode='subtract', opacity=0.5)
    g.n('col', 'gradient_map', {'in': 'mm'}, color_0=[x * 0.7 for x in c], color_1=c, color_2=[min(1, x * 1.2) for x in c])
    g.p('base_color', 'col.color_1')
    g.p('dark_color', 'col.color_0')
    g.p('light_color', 'col.color_2')
    g.n('rough', 'levels', {'in': 'f'}, out_low=rough[0], out_high=rough[1])
    g.p('roughness_min', 'rough.out_low')
    g.p('roughness_max', 'rough.out_high')
    finish(g, 'mm', 'rough', 'col', relief)


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
    g.n('rough', 'levels', {'in': 'lv'}, out_low=0.2, out_high=0.35)
    g.p('roughness_min', 'rough.out_low')
    g.p('roughness_max', 'rough.out_high')
    finish(g, 'lv', 'rough', 'col', 0.001)


venetian()


def paint(name, desc, col, scale, rough, relief, seed):
    g = G(name, 'paint', desc)
    g.n('f', 'fbm', scale_x=scale, scale_y=scale, octaves=4, roughness=0.5, seed=seed)
    g.n('c', 'uniform_color', color=col)
    g.p('paint_color', 'c.color')
    g.n('sh', 'levels', {'in': 'f'}, out_low=0.96, out_high=1.0)
    g.p('color_variation', 'sh.out_low', min=0.8, max=1.0)
    g.n('alb', 'blend', {'fg': 'sh', 'bg': 'c'}, mode='multiply')
    g.n('rough', 'levels', {'in': 'f'}, out_low=rough[0], out_high=rough[1])
    g.p('roughness_min', 'rough.out_low')
    g.p('roughness_max', 'rough.out_high')
    finish(g, 'f', 'rough', 'alb', relief)


paint('paint_matte_wall', 'Matte painted wall (roller texture).', [0.75, 0.73, 0.68], 48, (0.8, 0.9), 0.004, 121)
paint('paint_eggshell', 'Eggshell paint, slight sheen, colored.', [0.45, 0.55, 0.62], 64, (0.4, 0.5), 0.002, 123)
paint('paint_glossy', 'Glossy enamel paint (doors, trim).', [0.9, 0.9, 0.88], 8, (0.08, 0.12), 0.001, 125)


def textured_wall():
    g = G('paint_textured_wall', 'paint', 'Painted textured wall (knock-down): flattened blobs.')
    g.n('v', 'voronoi', scale=16, jitter=1.0, mode='f1', seed=131)
    g.n('f', 'fbm', scale_x=16, scale_y=16, octaves=4, roughness=0.5, seed=132)
    g.n('m', 'blend', {'fg': 'f', 'bg': 'v'}, mode='add', opacity=0.6)
    g.n('hs', 'histogram_scan', {'in': 'm'}, position=0.45, contrast=0.6)
    g.p('blob_coverage', 'hs.position', min=0.2, max=0.8)
    g.p('blob_sharpness', 'hs.contrast', min=0.0, max=0.9)
    g.n('c', 'uniform_color', color=[0.8, 0.77, 0.7])
    g.p('paint_color', 'c.color')
    g.n('sh', 'levels', {'in': 'hs'}, out_low=0.92, out_high=1.0)
    g.p('shade', 'sh.out_low', min=0.7, max=1.0)
    g.n('alb', 'blend', {'fg': 'sh', 'bg': 'c'}, mode='multiply')
    g.n('rough', 'levels', {'in': 'hs'}, out_low=0.85, out_high=0.7)
    g.p('roughness_low', 'rough.out_low')
    g.p('roughness_high', 'rough.out_high')
    finish(g, 'hs', 'rough', 'alb', 0.004)


textured_wall()

# ---------------------------------------------------------------- wallpaper
def wallpaper_stripes():
    g = G('wallpaper_stripes', 'wallpaper', 'Striped wallpaper: two-tone vertical stripes with a pinstripe, paper texture.')
    g.n('s', 'stripes', count=8, direction='u', width=0.5, softness=0.01)
    g.n('pin', 'stripes', count=8, direction='u', width=0.04, softness=0.01)
    g.p('stripe_count', 's.count', min=2, max=24)
    g.p('stripe_width', 's.width', min=0.1, max=0.9)
    g.p('stripe_count_pin', 'pin.count', min=2, max=24)
    g.n('ca', 'uniform_color', color=[0.72, 0.66, 0.5])
    g.n('cb', 'uniform_color', color=[0.55, 0.48, 0.32])
    g.n('cp', 'uniform_color', color=[0.45, 0.22, 0.15])
    g.p('color_a', 'ca.color')
    g.p('color_b', 'cb.color')
    g.p('pin_color', 'cp.color')
    g.n('m1', 'blend', {'fg': 'ca', 'bg': 'cb', 'mask': 's'})
    g.n('pin2', 'transform', {'in': 'pin'}, offset_u=0.0625)
    g.n('m2', 'blend', {'fg': 'cp', 'bg': 'm1', 'mask': 'pin2'})
    g.n('paper', 'fbm', scale_x=64, scale_y=64, octaves=3, roughness=0.5, seed=141)
    g.n('alb', 'blend', {'fg': 'paper', 'bg': 'm2'}, mode='overlay', opacity=0.15)
    g.p('paper_texture', 'alb.opacity')
    g.n('rough', 'levels', {'in': 's'}, out_low=0.75, out_high=0.6)
    g.p('roughness_a', 'rough.out_high')
    g.p('roughness_b', 'rough.out_low')
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
    g.n('ca', 'uniform_color', color=[0.35, 0.08, 0.1])
    g.n('cb', 'uniform_color', color=[0.5, 0.15, 0.15])
    g.p('ground_color', 'ca.color')
    g.p('ornament_color', 'cb.color')
    g.n('m', 'blend', {'fg': 'cb', 'bg': 'ca', 'mask': 'ornament'})
    g.n('paper', 'fbm', scale_x=64, scale_y=64, octaves=3, roughness=0.5, seed=152)
    g.n('alb', 'blend', {'fg': 'paper', 'bg': 'm'}, mode='overlay', opacity=0.1)
    g.n('rough', 'levels', {'in': 'ornament'}, out_low=0.8, out_high=0.45)
    g.p('roughness_ground', 'rough.out_low')
    g.p('roughness_ornament', 'rough.out_high')
    finish(g, 'ornament', 'rough', 'alb', 0.003, shift=(1 / 16, 1 / 16))


wallpaper_damask()


def wallpaper_grasscloth():
    g = G('wallpaper_grasscloth', 'wallpaper', 'Grasscloth wallpaper: horizontal natural fibers.')
    g.n('f', 'fbm', scale_x=2, scale_y=128, octaves=3, roughness=0.6, seed=161)
    g.n('f2', 'fbm', scale_x=8, scale_y=32, octaves=3, roughness=0.5, seed=162)
    g.n('m', 'blend', {'fg': 'f2', 'bg': 'f'}, mode='overlay', opacity=0.5)
    g.p('fiber_mix', 'm.opacity')
    colors3(g, 'col', 'm', [0.35, 0.3, 0.2], [0.55, 0.48, 0.34], [0.7, 0.64, 0.5])
    g.n('rough', 'levels', {'in': 'm'}, out_low=0.85, out_high=0.7)
    g.p('roughness_min', 'rough.out_high')
    g.p('roughness_max', 'rough.out_low')
    finish(g, 'm', 'rough', 'col', 0.004)


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
    g.n('m', 'blend', {'fg': 't.sampled', 'bg': 't.random'}, mode='overlay', opacity=0.5)
    g.p('brick_texture', 'm.opacity')
    colors3(g, 'col', 'm', [c * 0.5 for c in col], col, [min(1, c * 1.3) for c in col], 0.5, 'brick')
    g.n('mc', 'uniform_color', color=mortar)
    g.p('mortar_color', 'mc.color')
    g.n('edge', 'blend', {'fg': 'f', 'bg': 't.height'}, mode='multiply', opacity=0.4)
    g.n('mask', 'histogram_scan', {'in': 'edge'}, position=0.6, contrast=0.7)
    g.n('alb', 'blend', {'fg': 'col', 'bg': 'mc', 'mask': 'mask'})
    g.n('h', 'blend', {'fg': 'f', 'bg': 't.height'}, mode='multiply', opacity=0.3)
    g.n('rough', 'levels', {'in': 'f'}, out_low=0.75, out_high=0.95)
    g.p('roughness_min', 'rough.out_low')
    g.p('roughness_max', 'rough.out_high')
    finish(g, 'h', 'rough', 'alb', 0.008)


brick('brick_red', 'Red clay brick wall, running bond, grey mortar.', [0.4, 0.14, 0.08], [0.55, 0.53, 0.5], 12, 4, 171)
brick('brick_white_painted', 'Painted white brick wall.', [0.78, 0.77, 0.74], [0.7, 0.69, 0.66], 12, 4, 173)
brick('brick_yellow', 'Yellow / buff London stock brick, dark mortar.', [0.55, 0.42, 0.25], [0.3, 0.29, 0.27], 14, 4, 175)

# ---------------------------------------------------------------- fabric / carpet / leather
def fabric(name, desc, pattern, count, col, width, fuzz, seed, cat='fabric', rough=(0.85, 0.95), shift=None):
    g = G(name, cat, desc)
    g.n('w', 'weave', count=count, pattern=pattern, width=width, seed=seed)
    g.p('thread_count', 'w.count', min=max(4, count // 2), max=count * 2)
    g.p('thread_width', 'w.width', min=0.5, max=1.0)
    g.n('fz', 'fbm', scale_x=count * 2, scale_y=count * 2, octaves=2, roughness=0.5, seed=seed + 1)
    g.n('hf', 'blend', {'fg': 'fz', 'bg': 'w.height'}, mode='overlay', opacity=fuzz)
    g.p('fuzz', 'hf.opacity')
    g.n('tv', 'blend', {'fg': 'w.random', 'bg': 'hf'}, mode='overlay', opacity=0.3)
    g.p('thread_variation', 'tv.opacity')
    g.n('wc', 'uniform_color', color=col)
    g.n('fc', 'uniform_color', color=[c * 0.85 for c in col])
    g.p('warp_color', 'wc.color')
    g.p('weft_color', 'fc.color')
    g.n('cm', 'blend', {'fg': 'wc', 'bg': 'fc', 'mask': 'w.warp'})
    g.n('sh', 'levels', {'in': 'tv'}, out_low=0.45, out_high=1.0)
    g.p('shadowing', 'sh.out_low', min=0.1, max=1.0)
    g.n('alb', 'blend', {'fg': 'sh', 'bg': 'cm'}, mode='multiply')
    g.n('rough', 'levels', {'in': 'hf'}, out_low=rough[0], out_high=rough[1])
    g.p('roughness_min', 'rough.out_low')
    g.p('roughness_max', 'rough.out_high')
    # shift: half a thread, so the border runs along thread centres, not between threads
    finish(g, 'hf', 'rough', 'alb', 0.002, shift=(0.5 / count, 0.5 / count) if shift else None)


fabric('fabric_plain_weave', 'Plain-weave cotton / linen upholstery.', 'plain', 64, [0.55, 0.5, 0.42], 0.85, 0.3, 181)
fabric('fabric_twill', 'Twill (denim-like) fabric with diagonal ribs.', 'twill_2_2', 96, [0.12, 0.18, 0.35], 0.9, 0.25, 183)
fabric('fabric_basket', 'Basket-weave upholstery (panama), coarse.', 'basket_2_2', 48, [0.42, 0.36, 0.3], 0.85, 0.35, 185)
fabric('fabric_linen', 'Loose linen with slubby, irregular threads.', 'plain', 48, [0.68, 0.64, 0.56], 0.7, 0.6, 187)


def knit():
    g = G('fabric_knit', 'fabric', 'Knitted fabric: columns of V-shaped stitches.')
    g.n('sh', 'shape', count=24, shape='bell', size=1.0)
    g.n('zig', 'stripes', count=24, direction='diagonal', width=0.5, softness=0.3)
    g.n('zig2', 'stripes', count=24, direction='antidiagonal', width=0.5, softness=0.3)
    g.n('col', 'gradient_linear', direction='u', repeats=24, shape='saw')
    g.n('vv', 'blend', {'fg': 'zig', 'bg': 'zig2', 'mask': 'col'})
    g.n('st', 'blend', {'fg': 'sh', 'bg': 'vv'}, mode='multiply', opacity=0.5)
    g.p('stitch_roundness', 'st.opacity')
    g.p('stitch_softness', 'zig.softness', min=0.05, max=0.5)
    g.n('fz', 'fbm', scale_x=64, scale_y=64, octaves=2, roughness=0.5, seed=191)
    g.n('h', 'blend', {'fg': 'fz', 'bg': 'st'}, mode='overlay', opacity=0.3)
    g.p('fuzz', 'h.opacity')
    g.n('c', 'uniform_color', color=[0.5, 0.12, 0.1])
    g.p('yarn_color', 'c.color')
    g.n('s', 'levels', {'in': 'h'}, out_low=0.4, out_high=1.0)
    g.p('shadowing', 's.out_low', min=0.1, max=1.0)
    g.n('alb', 'blend', {'fg': 's', 'bg': 'c'}, mode='multiply')
    g.n('rough', 'levels', {'in': 'h'}, out_low=0.95, out_high=0.85)
    g.p('roughness_min', 'rough.out_high')
    g.p('roughness_max', 'rough.out_low')
    finish(g, 'h', 'rough', 'alb', 0.003)


knit()


def velvet():
    g = G('fabric_velvet', 'fabric', 'Velvet: dense pile with soft, directional sheen patches.')
    g.n('f', 'fbm', scale_x=3, scale_y=3, octaves=4, roughness=0.5, seed=201)
    g.n('pile', 'fbm', scale_x=128, scale_y=128, octaves=2, roughness=0.5, seed=202)
    g.n('dirb', 'directional_blur', {'in': 'f'}, length=0.05, angle=0.2, taps=8)
    g.p('crush_direction', 'dirb.angle')
    g.p('crush_length', 'dirb.length', min=0.0, max=0.15)
    g.n('m', 'blend', {'fg': 'pile', 'bg': 'dirb'}, mode='overlay', opacity=0.3)
    colors3(g, 'col', 'm', [0.13, 0.035, 0.045], [0.18, 0.05, 0.062], [0.25, 0.078, 0.092])
    g.n('rough', 'levels', {'in': 'm'}, out_low=0.7, out_high=0.9)
    g.p('roughness_min', 'rough.out_low')
    g.p('roughness_max', 'rough.out_high')
    finish(g, 'm', 'rough', 'col', 0.003)


velvet()


def carpet(name, desc, col, scale, loop, seed):
    g = G(name, 'carpet', desc)
    if loop:
        g.n('s', 'shape', count=scale, shape='bell', size=1.0)
        g.n('o', 'transform', {'in': 's'}, offset_u=0.5 / scale)
        g.n('p', 'blend', {'fg': 'o', 'bg': 's', 'mask': 'rowm'})
        g.n('rowm', 'stripes', count=scale // 2, direction='v', width=0.5, softness=0.01)
        g.p('loop_size', 's.size', min=0.5, max=1.0)
        pile = 'p'
    else:
        g.n('pn', 'white_noise', scale=scale * 4, seed=seed)
        g.n('pb', 'blur', {'in': 'pn'}, sigma=0.0015)
        g.p('tuft_softness', 'pb.sigma', min=0.0005, max=0.005)
        pile = 'pb'
    g.n('f', 'fbm', scale_x=4, scale_y=4, octaves=4, roughness=0.5, seed=seed + 1)
    g.n('m', 'blend', {'fg': 'f', 'bg': pile}, mode='overlay', opacity=0.5)
    g.p('mottling', 'm.opacity')
    g.n('c', 'gradient_map', {'in': 'm'}, color_0=[c * 0.5 for c in col], color_1=col, color_2=[min(1, c * 1.4) for c in col])
    g.p('pile_color', 'c.color_1')
    g.p('pile_shadow', 'c.color_0')
    g.p('pile_tip', 'c.color_2')
    g.n('rough', 'levels', {'in': 'm'}, out_low=0.9, out_high=1.0)
    g.p('roughness_min', 'rough.out_low')
    finish(g, 'm', 'rough', 'c', 0.004)


carpet('carpet_loop_pile', 'Berber-like loop pile carpet in rows.', [0.45, 0.4, 0.33], 48, True, 211)
carpet('carpet_cut_pile', 'Cut pile (plush) carpet, fine speckle.', [0.3, 0.32, 0.38], 64, False, 213)


def rug():
    g = G('carpet_patterned_rug', 'carpet', 'Patterned rug: bordered diamonds over cut pile.')
    g.n('d', 'checker', count=8, softness=0.02)
    g.n('dr', 'stripes', count=8, direction='diagonal', width=0.3, softness=0.05)
    g.n('dr2', 'stripes', count=8, direction='antidiagonal', width=0.3, softness=0.05)
    g.n('dd', 'blend', {'fg': 'dr', 'bg': 'dr2'}, mode='max')
    g.p('motif_line_width', 'dr.width', min=0.1, max=0.6)
    g.n('ca', 'uniform_color', color=[0.45, 0.08, 0.06])
    g.n('cb', 'uniform_color', color=[0.08, 0.1, 0.25])
    g.n('cc', 'uniform_color', color=[0.75, 0.65, 0.45])
    g.p('field_color', 'ca.color')
    g.p('motif_color', 'cb.color')
    g.p('line_color', 'cc.color')
    g.n('m1', 'blend', {'fg': 'cb', 'bg': 'ca', 'mask': 'd'})
    g.n('m2', 'blend', {'fg': 'cc', 'bg': 'm1', 'mask': 'dd'})
    g.n('pn', 'white_noise', scale=256, seed=221)
    g.n('pb', 'blur', {'in': 'pn'}, sigma=0.0015)
    g.n('wr', 'warp', {'in': 'm2', 'height': 'pb'}, intensity=0.0005)
    g.p('pile_disorder', 'wr.intensity', min=0.0, max=0.002)
    g.n('alb', 'blend', {'fg': 'pb', 'bg': 'wr'}, mode='overlay', opacity=0.3)
    g.p('pile_texture', 'alb.opacity')
    g.n('rough', 'levels', {'in': 'pb'}, out_low=0.9, out_high=1.0)
    finish(g, 'pb', 'rough', 'alb', 0.003)


rug()


def leather(name, desc, col, scale, rough, seed):
    g = G(name, 'leather', desc)
    g.n('v', 'voronoi', scale=scale, jitter=1.0, mode='f2_minus_f1', seed=seed)
    g.n('cr', 'histogram_scan', {'in': 'v'}, position=0.8, contrast=0.6)
    g.p('crease_width', 'cr.position', min=0.5, max=0.98)
    g.n('f', 'fbm', scale_x=4, scale_y=4, octaves=5, roughness=0.55, seed=seed + 1)
    g.n('m', 'blend', {'fg': 'f', 'bg': 'cr'}, mode='overlay', opacity=0.4)
    g.p('wear', 'm.opacity')
    colors3(g, 'col', 'm', [c * 0.5 for c in col], col, [min(1, c * 1.3) for c in col], 0.5, 'leather')
    g.n('rough', 'levels', {'in': 'cr'}, out_low=rough[1], out_high=rough[0])
    g.p('roughness_grain', 'rough.out_low')
    g.p('roughness_top', 'rough.out_high')
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
    g.n('rough', 'levels', {'in': 'lv'}, out_low=0.25, out_high=0.4)
    g.p('roughness_min', 'rough.out_low')
    g.p('roughness_max', 'rough.out_high')
    g.n('metal', 'uniform_gray', value=1.0)
    g.p('metallic', 'metal.value')
    finish(g, 'lv', 'rough', 'col', 0.0005, metallic='metal')


brushed_metal()


def painted_metal():
    g = G('metal_painted', 'metal', 'Powder-coated / painted metal with slight orange peel and chips.')
    g.n('op', 'fbm', scale_x=48, scale_y=48, octaves=3, roughness=0.5, seed=251)
    g.n('ch', 'fbm', scale_x=6, scale_y=6, octaves=6, roughness=0.6, seed=252)
    g.n('chips', 'histogram_scan', {'in': 'ch'}, position=0.1, contrast=0.9)
    g.p('chipping', 'chips.position', min=0.0, max=0.4)
    g.n('paint', 'uniform_color', color=[0.1, 0.25, 0.2])
    g.p('paint_color', 'paint.color')
    g.n('bare', 'uniform_color', color=[0.6, 0.6, 0.62])
    g.p('metal_color', 'bare.color')
    g.n('alb', 'blend', {'fg': 'bare', 'bg': 'paint', 'mask': 'chips'})
    g.n('inv', 'invert', {'in': 'chips'})
    g.n('h', 'blend', {'fg': 'op', 'bg': 'inv'}, mode='multiply', opacity=0.1)
    g.n('rough', 'levels', {'in': 'chips'}, out_low=0.35, out_high=0.5)
    g.p('roughness_paint', 'rough.out_low')
    g.p('roughness_bare', 'rough.out_high')
    g.n('metal', 'levels', {'in': 'chips'}, out_low=0.0, out_high=0.9)
    g.p('bare_metallic', 'metal.out_high')
    finish(g, 'h', 'rough', 'alb', 0.003, metallic='metal')


painted_metal()


def plastic(name, desc, col, rough, bump, scale, seed):
    g = G(name, 'plastic', desc)
    g.n('f', 'fbm', scale_x=scale, scale_y=scale, octaves=4, roughness=0.5, seed=seed)
    g.n('c', 'uniform_color', color=col)
    g.p('color', 'c.color')
    g.n('sh', 'levels', {'in': 'f'}, out_low=0.97, out_high=1.0)
    g.p('color_variation', 'sh.out_low', min=0.8, max=1.0)
    g.n('alb', 'blend', {'fg': 'sh', 'bg': 'c'}, mode='multiply')
    g.n('rough', 'levels', {'in': 'f'}, out_low=rough[0], out_high=rough[1])
    g.p('roughness_min', 'rough.out_low')
    g.p('roughness_max', 'rough.out_high')
    finish(g, 'f', 'rough', 'alb', bump)


plastic('plastic_glossy', 'Glossy molded plastic (appliances, furniture).', [0.8, 0.8, 0.78], (0.05, 0.1), 0.0005, 8, 261)
plastic('plastic_textured', 'Textured (sand-blasted) matte plastic.', [0.15, 0.15, 0.16], (0.5, 0.65), 0.006, 96, 263)
plastic('plastic_laminate', 'Colored laminate worktop with fine speckle.', [0.55, 0.2, 0.15], (0.25, 0.35), 0.002, 128, 265)


def cork():
    g = G('cork', 'cork', 'Agglomerated cork board / floor: granules of varied brown.')
    g.n('v', 'voronoi', scale=64, jitter=1.0, mode='cell_value', seed=271)
    g.n('e', 'voronoi', scale=64, jitter=1.0, mode='f2_minus_f1', seed=271)
    g.n('ed', 'histogram_scan', {'in': 'e'}, position=0.85, contrast=0.6)
    g.p('granule_gaps', 'ed.position', min=0.6, max=1.0)
    g.n('f', 'fbm', scale_x=16, scale_y=16, octaves=4, roughness=0.5, seed=272)
    g.n('m', 'blend', {'fg': 'f', 'bg': 'v'}, mode='overlay', opacity=0.5)
    g.n('m2', 'blend', {'fg': 'ed', 'bg': 'm'}, mode='multiply', opacity=0.6)
    g.p('gap_darkness', 'm2.opacity')
    colors3(g, 'col', 'm2', [0.2, 0.12, 0.06], [0.45, 0.3, 0.17], [0.62, 0.45, 0.28])
    g.n('rough', 'levels', {'in': 'm'}, out_low=0.8, out_high=0.9)
    g.p('roughness_min', 'rough.out_low')
    g.p('roughness_max', 'rough.out_high')
    finish(g, 'm2', 'rough', 'col', 0.005)


cork()


def rubber():
    g = G('rubber_studded', 'rubber', 'Studded rubber flooring: round raised studs on a matte base.')
    g.n('s', 'shape', count=12, shape='disc', size=0.55, softness=0.08)
    g.p('stud_count', 's.count', min=4, max=32)
    g.p('stud_size', 's.size', min=0.2, max=0.9)
    g.p('stud_edge', 's.softness', min=0.02, max=0.3)
    g.n('f', 'fbm', scale_x=64, scale_y=64, octaves=3, roughness=0.5, seed=281)
    g.n('h', 'blend', {'fg': 'f', 'bg': 's'}, mode='add', opacity=0.03)
    g.n('c', 'uniform_color', color=[0.08, 0.08, 0.085])
    g.p('rubber_color', 'c.color')
    g.n('sh', 'levels', {'in': 'f'}, out_low=0.85, out_high=1.0)
    g.n('alb', 'blend', {'fg': 'sh', 'bg': 'c'}, mode='multiply')
    g.n('rough', 'levels', {'in': 's'}, out_low=0.8, out_high=0.6)
    g.p('roughness_base', 'rough.out_low')
    g.p('roughness_stud', 'rough.out_high')
    finish(g, 'h', 'rough', 'alb', 0.01)


rubber()


def rubber_plain():
    g = G('rubber_plain', 'rubber', 'Plain rubber / linoleum sheet with fine flecks.')
    g.n('f', 'white_noise', scale=512, seed=291)
    g.n('fl', 'histogram_scan', {'in': 'f'}, position=0.06, contrast=0.95)
    g.p('fleck_amount', 'fl.position', min=0.0, max=0.3)
    g.n('c', 'uniform_color', color=[0.35, 0.38, 0.33])
    g.n('fc', 'uniform_color', color=[0.75, 0.75, 0.72])
    g.p('base_color', 'c.color')
    g.p('fleck_color', 'fc.color')
    g.n('alb', 'blend', {'fg': 'fc', 'bg': 'c', 'mask': 'fl'})
    g.n('b', 'fbm', scale_x=16, scale_y=16, octaves=4, roughness=0.5, seed=292)
    g.n('rough', 'levels', {'in': 'b'}, out_low=0.55, out_high=0.7)
    g.p('roughness_min', 'rough.out_low')
    g.p('roughness_max', 'rough.out_high')
    finish(g, 'b', 'rough', 'alb', 0.002, shift=(1 / 1024, 1 / 1024), snap=False)


rubber_plain()


def paper(name, desc, col, fibers, seed, corrugated=False):
    g = G(name, 'paper', desc)
    g.n('f', 'fbm', scale_x=fibers, scale_y=fibers, octaves=5, roughness=0.6, seed=seed)
    g.n('c', 'uniform_color', color=col)
    g.p('paper_color', 'c.color')
    g.n('sh', 'levels', {'in': 'f'}, out_low=0.9, out_high=1.0)
    g.p('mottling', 'sh.out_low', min=0.6, max=1.0)
    g.n('alb', 'blend', {'fg': 'sh', 'bg': 'c'}, mode='multiply')
    h = 'f'
    if corrugated:
        g.n('rib', 'stripes', count=24, direction='v', width=0.5, softness=0.4)
        g.n('hh', 'blend', {'fg': 'f', 'bg': 'rib'}, mode='multiply', opacity=0.2)
        g.p('rib_count', 'rib.count', min=8, max=64)
        h = 'hh'
    g.n('rough', 'levels', {'in': 'f'}, out_low=0.8, out_high=0.95)
    g.p('roughness_min', 'rough.out_low')
    g.p('roughness_max', 'rough.out_high')
    finish(g, h, 'rough', 'alb', 0.002, shift=(0, 1 / 96) if corrugated else None)


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
    g.n('fz', 'fbm', scale_x=min(256, threads * 2), scale_y=min(256, threads * 2), octaves=2, roughness=0.5, seed=seed + 1)
    g.n('hf', 'blend', {'fg': 'fz', 'bg': 'w.height'}, mode='overlay', opacity=0.25)
    g.p('fuzz', 'hf.opacity')
    g.n('su', 'stripes', count=stripe_count, direction='u', width=width, softness=0.002)
    g.n('sv', 'stripes', count=stripe_count, direction='v', width=width, softness=0.002)
    g.p('stripe_width', 'su.width', 'sv.width', min=min(0.2, width), max=0.8)
    g.n('ca', 'uniform_color', color=colors[0])
    g.n('cb', 'uniform_color', color=colors[1])
    g.p('ground_color', 'ca.color')
    g.p('stripe_color', 'cb.color')
    g.n('cu', 'blend', {'fg': 'cb', 'bg': 'ca', 'mask': 'su'})
    g.n('cv', 'blend', {'fg': 'cb', 'bg': 'ca', 'mask': 'sv'})
    if pin is not None:  # a second, narrow stripe (tartan over-check)
        g.n('pu', 'stripes', count=pin[0], direction='u', width=pin[1], softness=0.002)
        g.n('pv', 'stripes', count=pin[0], direction='v', width=pin[1], softness=0.002)
        g.p('overcheck_width', 'pu.width', 'pv.width', min=0.05, max=0.4)
        g.n('cp', 'uniform_color', color=colors[2])
        g.p('overcheck_color', 'cp.color')
        g.n('cu2', 'blend', {'fg': 'cp', 'bg': 'cu', 'mask': 'pu'})
        g.n('cv2', 'blend', {'fg': 'cp', 'bg': 'cv', 'mask': 'pv'})
        cu, cv = 'cu2', 'cv2'
    else:
        cu, cv = 'cu', 'cv'
    g.n('cm', 'blend', {'fg': cu, 'bg': cv, 'mask': 'w.warp'})
    g.n('sh', 'levels', {'in': 'hf'}, out_low=0.55, out_high=1.0)
    g.p('shadowing', 'sh.out_low', min=0.2, max=1.0)
    g.n('alb', 'blend', {'fg': 'sh', 'bg': 'cm'}, mode='multiply')
    g.n('rough', 'levels', {'in': 'hf'}, out_low=rough[0], out_high=rough[1])
    g.p('roughness_min', 'rough.out_low')
    g.p('roughness_max', 'rough.out_high')
    finish(g, 'hf', 'rough', 'alb', 0.002)


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
    g.n('h', 'blend', {'fg': 'h2', 'bg': 'w.height', 'mask': 'band'})
    g.n('m', 'blend', {'fg': 'm2', 'bg': 'w.warp', 'mask': 'band'})
    g.n('fz', 'fbm', scale_x=192, scale_y=192, octaves=2, roughness=0.5, seed=412)
    g.n('hf', 'blend', {'fg': 'fz', 'bg': 'h'}, mode='overlay', opacity=0.3)
    g.p('fuzz', 'hf.opacity')
    g.n('ca', 'uniform_color', color=[0.12, 0.11, 0.1])
    g.n('cb', 'uniform_color', color=[0.45, 0.42, 0.37])
    g.p('warp_color', 'ca.color')
    g.p('weft_color', 'cb.color')
    g.n('cm', 'blend', {'fg': 'ca', 'bg': 'cb', 'mask': 'm'})
    g.n('sh', 'levels', {'in': 'hf'}, out_low=0.5, out_high=1.0)
    g.p('shadowing', 'sh.out_low', min=0.2, max=1.0)
    g.n('alb', 'blend', {'fg': 'sh', 'bg': 'cm'}, mode='multiply')
    g.n('rough', 'levels', {'in': 'hf'}, out_low=0.85, out_high=0.95)
    g.p('roughness_min', 'rough.out_low')
    g.p('roughness_max', 'rough.out_high')
    finish(g, 'hf', 'rough', 'alb', 0.002)


fabric_herringbone()


def quilted(name, desc, count, col, tufted=False, seed=421):
    """Diamond quilting: puffs between diagonal stitch lines (the product of two triangle waves);
    tufted: deeper puffs and a button at every stitch crossing."""
    g = G(name, 'fabric', desc)
    g.n('d1', 'stripes', count=count, direction='diagonal', width=0.5, softness=0.5)
    g.n('d2', 'stripes', count=count, direction='antidiagonal', width=0.5, softness=0.5)
    g.n('pf', 'blend', {'fg': 'd1', 'bg': 'd2'}, mode='multiply')
    g.n('puff', 'levels', {'in': 'pf'}, gamma=2.5 if tufted else 1.8)
    g.p('puffiness', 'puff.gamma', min=1.0, max=4.0)
    g.n('w', 'weave', count=128, pattern='plain', width=0.9, seed=seed)
    g.n('hs', 'blend', {'fg': 'w.height', 'bg': 'puff'}, mode='add', opacity=0.06)
    g.p('weave_relief', 'hs.opacity', min=0.0, max=0.2)
    g.n('c', 'uniform_color', color=col)
    g.p('cloth_color', 'c.color')
    g.n('sh', 'levels', {'in': 'puff'}, out_low=0.45 if tufted else 0.65, out_high=1.0)
    g.p('fold_shadow', 'sh.out_low', min=0.1, max=1.0)
    g.n('alb0', 'blend', {'fg': 'sh', 'bg': 'c'}, mode='multiply')
    alb, h = 'alb0', 'hs'
    if tufted:
        g.n('bt', 'shape', count=count, shape='disc', size=0.12, softness=0.04)
        g.n('btc', 'uniform_color', color=[c * 0.5 for c in col])
        g.p('button_color', 'btc.color')
        g.n('alb', 'blend', {'fg': 'btc', 'bg': 'alb0', 'mask': 'bt'})
        g.n('hb', 'blend', {'fg': 'bt', 'bg': 'hs'}, mode='add', opacity=0.2)
        alb, h = 'alb', 'hb'
    g.n('rough', 'levels', {'in': 'puff'}, out_low=0.95, out_high=0.8)
    g.p('roughness_folds', 'rough.out_low')
    g.p('roughness_top', 'rough.out_high')
    finish(g, h, 'rough', alb, 0.02 if tufted else 0.012, normal_max=0.1)


quilted('fabric_quilted', 'Diamond-quilted upholstery / bedspread: soft puffs between stitched diagonal lines.', 6, [0.55, 0.5, 0.45])
quilted('fabric_tufted', 'Tufted (capitonne) upholstery: deep diamond puffs with a button at every crossing.', 4, [0.12, 0.2, 0.15], True, 423)


def corduroy():
    g = G('fabric_corduroy', 'fabric', 'Corduroy: parallel rounded pile ribs (wales) along v.')
    g.n('rib', 'stripes', count=24, direction='u', width=0.7, softness=0.5)
    g.p('wale_count', 'rib.count', min=8, max=64)
    g.p('wale_width', 'rib.width', min=0.3, max=0.95)
    g.n('pile', 'fbm', scale_x=128, scale_y=32, octaves=3, roughness=0.5, seed=431)
    g.n('h', 'blend', {'fg': 'pile', 'bg': 'rib'}, mode='overlay', opacity=0.3)
    g.p('pile_texture', 'h.opacity')
    colors3(g, 'col', 'h', [0.18, 0.1, 0.05], [0.32, 0.19, 0.1], [0.42, 0.27, 0.15], 0.5, 'pile')
    g.n('rough', 'levels', {'in': 'h'}, out_low=0.95, out_high=0.8)
    g.p('roughness_groove', 'rough.out_low')
    g.p('roughness_top', 'rough.out_high')
    finish(g, 'h', 'rough', 'col', 0.004, shift=(0.5 / 24, 0))  # the border on a wale's crest, not in a groove's cusp


corduroy()


def knit2(name, desc, count, col, seed):
    g = G(name, 'fabric', desc)
    g.n('sh', 'shape', count=count, shape='bell', size=1.0)
    g.n('zig', 'stripes', count=count, direction='diagonal', width=0.5, softness=0.3)
    g.n('zig2', 'stripes', count=count, direction='antidiagonal', width=0.5, softness=0.3)
    g.n('col', 'gradient_linear', direction='u', repeats=count, shape='saw')
    g.n('vv', 'blend', {'fg': 'zig', 'bg': 'zig2', 'mask': 'col'})
    g.n('st', 'blend', {'fg': 'sh', 'bg': 'vv'}, mode='multiply', opacity=0.5)
    g.p('stitch_roundness', 'st.opacity')
    g.p('stitch_softness', 'zig.softness', min=0.05, max=0.5)
    g.n('fz', 'fbm', scale_x=min(256, count * 4), scale_y=min(256, count * 4), octaves=2, roughness=0.5, seed=seed)
    g.n('h', 'blend', {'fg': 'fz', 'bg': 'st'}, mode='overlay', opacity=0.3)
    g.p('fuzz', 'h.opacity')
    g.n('c', 'uniform_color', color=col)
    g.p('yarn_color', 'c.color')
    g.n('s', 'levels', {'in': 'h'}, out_low=0.35, out_high=1.0)
    g.p('shadowing', 's.out_low', min=0.1, max=1.0)
    g.n('alb', 'blend', {'fg': 's', 'bg': 'c'}, mode='multiply')
    g.n('rough', 'levels', {'in': 'h'}, out_low=0.95, out_high=0.85)
    g.p('roughness_min', 'rough.out_high')
    g.p('roughness_max', 'rough.out_low')
    finish(g, 'h', 'rough', 'alb', 0.006, shift=(0.5 / count, 0.5 / count))


knit2('fabric_knit_chunky', 'Chunky hand knit (throws, cushions): large V stitches of thick wool.', 8, [0.72, 0.7, 0.64], 441)

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
    g.n('rf', 'blend', {'fg': 'rush', 'bg': 'rib.height'}, mode='overlay', opacity=0.4)
    g.p('rush_variation', 'rf.opacity')
    g.n('t', 'tile', {'pattern': 'rf'}, layout='grid', rows=1, cols=2, gap=0.0, bevel=0.02, lum_var=0.2, seed=473)
    g.n('edge', 'tile', layout='grid', rows=1, cols=2, gap=0.0, bevel=0.005, lum_var=0.0, seed=474)
    g.n('bm', 'histogram_scan', {'in': 't.height'}, position=0.9, contrast=0.9)
    g.p('border_width', 'bm.position', min=0.7, max=1.0)
    colors3(g, 'col', 't.sampled', [0.35, 0.33, 0.17], [0.55, 0.52, 0.3], [0.68, 0.64, 0.42], 0.5, 'rush')
    g.n('bc', 'uniform_color', color=[0.05, 0.06, 0.05])
    g.p('border_color', 'bc.color')
    g.n('alb', 'blend', {'fg': 'col', 'bg': 'bc', 'mask': 'bm'})
    g.n('h', 'blend', {'fg': 't.sampled', 'bg': 'bm'}, mode='multiply', opacity=0.3)
    g.n('rough', 'levels', {'in': 't.sampled'}, out_low=0.55, out_high=0.75)
    g.p('roughness_min', 'rough.out_low')
    g.p('roughness_max', 'rough.out_high')
    finish(g, 'h', 'rough', 'alb', 0.004, shift=(0.25, 0.5))


tatami()


def pile(g, seed, scale=256):
    g.n('pn', 'white_noise', scale=scale, seed=seed)
    g.n('pb', 'blur', {'in': 'pn'}, sigma=0.0015)
    g.p('tuft_softness', 'pb.sigma', min=0.0005, max=0.005)
    return 'pb'


def rug_striped():
    g = G('carpet_striped_rug', 'carpet', 'Striped rug / runner: bands of three colours across a cut or flat-woven pile.')
    g.n('s1', 'stripes', count=4, direction='v', width=0.5, softness=0.01)
    g.n('s2', 'stripes', count=12, direction='v', width=0.3, softness=0.01)
    g.p('band_width', 's1.width', min=0.2, max=0.8)
    g.p('pinstripe_width', 's2.width', min=0.05, max=0.6)
    g.n('ca', 'uniform_color', color=[0.7, 0.66, 0.58])
    g.n('cb', 'uniform_color', color=[0.12, 0.16, 0.25])
    g.n('cc', 'uniform_color', color=[0.5, 0.2, 0.1])
    g.p('ground_color', 'ca.color')
    g.p('band_color', 'cb.color')
    g.p('stripe_color', 'cc.color')
    g.n('m1', 'blend', {'fg': 'cb', 'bg': 'ca', 'mask': 's1'})
    g.n('m2', 'blend', {'fg': 'cc', 'bg': 'm1', 'mask': 's2'})
    p = pile(g, 481)
    g.n('wr', 'warp', {'in': 'm2', 'height': p}, intensity=0.0005)
    g.p('pile_disorder', 'wr.intensity', min=0.0, max=0.002)
    g.n('alb', 'blend', {'fg': p, 'bg': 'wr'}, mode='overlay', opacity=0.35)
    g.p('pile_texture', 'alb.opacity')
    g.n('rough', 'levels', {'in': p}, out_low=0.9, out_high=1.0)
    g.p('roughness_min', 'rough.out_low')
    finish(g, p, 'rough', 'alb', 0.003, shift=(0, 1 / 32))


rug_striped()


def rug_medallion():
    g = G('carpet_medallion_rug', 'carpet', 'Bordered rug: a field with a central diamond medallion, framed by a border band (one rug per texture tile).')
    g.n('tu', 'gradient_linear', direction='u', repeats=1, shape='triangle')
    g.n('tv', 'gradient_linear', direction='v', repeats=1, shape='triangle')
    # frame: distance to the rug's edge = min of the two triangles (0 at the edge, 1 at the centre)
    g.n('fr', 'blend', {'fg': 'tu', 'bg': 'tv'}, mode='min')
    g.n('border', 'histogram_scan', {'in': 'fr'}, position=0.85, contrast=0.97)
    g.p('border_width', 'border.position', min=0.7, max=0.97)
    g.n('line', 'histogram_scan', {'in': 'fr'}, position=0.8, contrast=0.97)
    # medallion: the L1 distance to the centre (mean of the two triangles)
    g.n('dia', 'blend', {'fg': 'tu', 'bg': 'tv'}, mode='copy', opacity=0.5)
    g.n('med', 'histogram_scan', {'in': 'dia'}, position=0.25, contrast=0.97)
    g.p('medallion_size', 'med.position', min=0.05, max=0.5)
    g.n('ca', 'uniform_color', color=[0.42, 0.06, 0.05])
    g.n('cb', 'uniform_color', color=[0.06, 0.08, 0.2])
    g.n('cc', 'uniform_color', color=[0.72, 0.62, 0.45])
    g.p('field_color', 'ca.color')
    g.p('border_color', 'cb.color')
    g.p('ornament_color', 'cc.color')
    g.n('motif', 'stripes', count=32, direction='diagonal', width=0.25, softness=0.1)
    g.n('mf', 'blend', {'fg': 'cc', 'bg': 'ca', 'mask': 'motif'}, opacity=0.3)
    g.p('field_pattern', 'mf.opacity')
    g.n('a1', 'blend', {'fg': 'cb', 'bg': 'mf', 'mask': 'med'})
    g.n('ib', 'invert', {'in': 'border'})
    g.n('a2', 'blend', {'fg': 'cb', 'bg': 'a1', 'mask': 'ib'})
    g.n('il', 'invert', {'in': 'line'})
    g.n('lm', 'blend', {'fg': 'il', 'bg': 'border'}, mode='multiply')
    g.n('a3', 'blend', {'fg': 'cc', 'bg': 'a2', 'mask': 'lm'})
    p = pile(g, 491)
    g.n('alb', 'blend', {'fg': p, 'bg': 'a3'}, mode='overlay', opacity=0.3)
    g.p('pile_texture', 'alb.opacity')
    g.n('rough', 'levels', {'in': p}, out_low=0.9, out_high=1.0)
    g.p('roughness_min', 'rough.out_low')
    finish(g, p, 'rough', 'alb', 0.003)


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
    g.n('rough', 'levels', {'in': 'lv'}, out_low=0.95, out_high=0.85)
    g.p('roughness_min', 'rough.out_high')
    g.p('roughness_max', 'rough.out_low')
    finish(g, 'lv', 'rough', 'col', 0.004)


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
    g.n('tc', 'uniform_color', color=[0.8, 0.79, 0.76])
    g.p('tile_color', 'tc.color')
    g.n('gc', 'uniform_color', color=[0.85, 0.85, 0.85])
    g.p('grid_color', 'gc.color')
    g.n('pc', 'uniform_color', color=[0.25, 0.24, 0.22])
    g.p('hole_color', 'pc.color')
    g.n('a0', 'blend', {'fg': 'pc', 'bg': 'tc', 'mask': 'pit'}, opacity=0.8)
    g.p('hole_darkness', 'a0.opacity')
    g.n('alb', 'blend', {'fg': 'a0', 'bg': 'gc', 'mask': 't.height'})
    g.n('rough', 'levels', {'in': 't.height'}, out_low=0.4, out_high=0.95)
    g.p('roughness_grid', 'rough.out_low')
    g.p('roughness_tile', 'rough.out_high')
    finish(g, 'depth', 'rough', 'alb', 0.004, shift=(0.25, 0.25))


ceiling_tile('tile_ceiling_fissured', 'Acoustic ceiling tiles (mineral fibre): white faces with random fissures, in a T-bar grid.', False, 511)
ceiling_tile('tile_ceiling_perforated', 'Perforated acoustic ceiling tiles: a regular grid of small holes, white grid.', True, 513)


def tile_herringbone():
    g = G('tile_herringbone', 'tile', 'Ceramic / porcelain tiles laid in herringbone with grout joints.')
    g.n('hb', 'herringbone', count=4, ratio=3, gap=0.12, bevel=0.1, lum_var=0.3, seed=521)
    g.p('grout_width', 'hb.gap', min=0.02, max=0.3)
    g.p('bevel', 'hb.bevel', min=0.02, max=0.3)
    g.p('tile_variation', 'hb.lum_var')
    g.n('cloud', 'fbm', scale_x=8, scale_y=8, octaves=4, roughness=0.5, seed=522)
    g.n('var', 'blend', {'fg': 'cloud', 'bg': 'hb.random'}, mode='overlay', opacity=0.3)
    g.p('surface_mottling', 'var.opacity')
    colors3(g, 'tc', 'var', [0.42, 0.45, 0.44], [0.55, 0.58, 0.57], [0.66, 0.69, 0.68], 0.5, 'tile')
    g.n('gc', 'uniform_color', color=[0.6, 0.6, 0.58])
    g.p('grout_color', 'gc.color')
    g.n('alb', 'blend', {'fg': 'tc', 'bg': 'gc', 'mask': 'hb.height'})
    g.n('rough', 'levels', {'in': 'hb.height'}, out_low=0.8, out_high=0.15)
    g.p('roughness_grout', 'rough.out_low')
    g.p('roughness_tile', 'rough.out_high')
    finish(g, 'hb.height', 'rough', 'alb', 0.008, shift=(1 / 64, 1 / 64))


tile_herringbone()


def zellige():
    g = G('tile_zellige', 'tile', 'Zellige: small handmade glazed tiles, strongly varied in tone, wavy glossy faces, thin joints.')
    g.n('t', 'tile', layout='grid', rows=8, cols=8, gap=0.04, bevel=0.08, lum_var=0.8, seed=531)
    g.p('grout_width', 't.gap', min=0.0, max=0.2)
    g.p('tile_variation', 't.lum_var')
    g.n('wave', 'fbm', scale_x=16, scale_y=16, octaves=4, roughness=0.5, seed=532)
    g.n('var', 'blend', {'fg': 'wave', 'bg': 't.random'}, mode='overlay', opacity=0.5)
    g.p('glaze_pooling', 'var.opacity')
    colors3(g, 'tc', 'var', [0.05, 0.2, 0.22], [0.12, 0.38, 0.4], [0.4, 0.62, 0.6], 0.5, 'glaze')
    g.n('gc', 'uniform_color', color=[0.7, 0.68, 0.63])
    g.p('grout_color', 'gc.color')
    g.n('alb', 'blend', {'fg': 'tc', 'bg': 'gc', 'mask': 't.height'})
    g.n('h', 'blend', {'fg': 'wave', 'bg': 't.height'}, mode='multiply', opacity=0.4)
    g.p('face_waviness', 'h.opacity')
    g.n('rough', 'levels', {'in': 't.height'}, out_low=0.8, out_high=0.06)
    g.p('roughness_grout', 'rough.out_low')
    g.p('roughness_glaze', 'rough.out_high')
    finish(g, 'h', 'rough', 'alb', 0.01, shift=(1 / 16, 1 / 16))


zellige()


def encaustic():
    g = G('tile_encaustic', 'tile', 'Encaustic / cement pattern tiles: a two-colour star-and-diamond motif repeated on every tile.')
    g.n('t', 'tile', layout='grid', rows=4, cols=4, gap=0.02, bevel=0.02, lum_var=0.1, seed=541)
    g.p('grout_width', 't.gap', min=0.0, max=0.1)
    g.n('tu', 'gradient_linear', direction='u', repeats=4, shape='triangle')
    g.n('tv', 'gradient_linear', direction='v', repeats=4, shape='triangle')
    g.n('dia', 'blend', {'fg': 'tu', 'bg': 'tv'}, mode='copy', opacity=0.5)
    g.n('m1', 'histogram_scan', {'in': 'dia'}, position=0.45, contrast=0.95)
    g.p('diamond_size', 'm1.position', min=0.2, max=0.7)
    g.n('sq', 'blend', {'fg': 'tu', 'bg': 'tv'}, mode='max')
    g.n('m2', 'histogram_scan', {'in': 'sq'}, position=0.3, contrast=0.95)
    g.p('star_size', 'm2.position', min=0.1, max=0.5)
    g.n('ca', 'uniform_color', color=[0.75, 0.73, 0.68])
    g.n('cb', 'uniform_color', color=[0.1, 0.16, 0.3])
    g.n('cc', 'uniform_color', color=[0.6, 0.35, 0.2])
    g.p('ground_color', 'ca.color')
    g.p('motif_color', 'cb.color')
    g.p('accent_color', 'cc.color')
    g.n('a1', 'blend', {'fg': 'cb', 'bg': 'ca', 'mask': 'm1'})
    g.n('a2', 'blend', {'fg': 'cc', 'bg': 'a1', 'mask': 'm2'})
    g.n('f', 'fbm', scale_x=16, scale_y=16, octaves=4, roughness=0.5, seed=542)
    g.n('a3', 'blend', {'fg': 'f', 'bg': 'a2'}, mode='overlay', opacity=0.15)
    g.p('wear', 'a3.opacity')
    g.n('gc', 'uniform_color', color=[0.55, 0.53, 0.5])
    g.n('alb', 'blend', {'fg': 'a3', 'bg': 'gc', 'mask': 't.height'})
    g.n('rough', 'levels', {'in': 'f'}, out_low=0.5, out_high=0.7)
    g.p('roughness_min', 'rough.out_low')
    g.p('roughness_max', 'rough.out_high')
    finish(g, 't.height', 'rough', 'alb', 0.004, shift=(1 / 8, 1 / 8))


encaustic()

# ---------------------------------------------------------------- wood: grains, panelling, laminate
def wood_plank_variant(name, desc, grain_fn, rows, cols, layout, col, seed, tint=0.5, lum_var=0.5, gap=0.02, bevel=0.03,
                       rough=(0.5, 0.38), shift=None):
    g = G(name, 'wood', desc)
    grain = grain_fn(g, seed)
    g.n('tiles', 'tile', {'pattern': grain}, layout=layout, rows=rows, cols=cols, row_offset=0.5 if layout == 'bricks' else 0.9,
        gap=gap, bevel=bevel, lum_var=lum_var, seed=seed)
    g.p('plank_gap', 'tiles.gap', min=0.0, max=0.1)
    g.p('plank_bevel', 'tiles.bevel', min=0.005, max=0.2)
    g.p('plank_variation', 'tiles.lum_var')
    c = wood_colors(g, 'tiles.sampled', *col)
    g.n('tint', 'blend', {'fg': 'tiles.random', 'bg': c}, mode='overlay', opacity=tint)
    g.p('plank_tint', 'tint.opacity', doc='per-plank brightness variation')
    g.n('gapm', 'invert', {'in': 'tiles.height'})
    g.n('gapc', 'uniform_color', color=[0.25, 0.2, 0.17])
    g.n('alb', 'blend', {'fg': 'gapc', 'bg': 'tint', 'mask': 'gapm'}, mode='multiply', opacity=1.0)
    g.n('h', 'blend', {'fg': grain, 'bg': 'tiles.height'}, mode='multiply', opacity=0.15)
    r = rough_from(g, grain, *rough)
    # shift: by default half a plank; the random row offsets of `planks` can still put a plank end
    # on the border, then a measured shift is given
    finish(g, 'h', r, 'alb', 0.005, normal_max=0.03,
           shift=shift or ((0.25 if layout == 'bricks' else 0.5) / cols, 0.5 / rows), shift_maps=('alb', 'hgt'))


def cathedral_grain(g, seed):
    """Flat-sawn grain: rings bent into nested arches (the 'cathedrals') by a triangle ramp
    across each plank-wide band, then wavy."""
    g.n('ring', 'stripes', count=24, direction='v', width=0.35, softness=0.35)
    g.n('tri', 'gradient_linear', direction='u', repeats=2, shape='triangle')
    g.n('arch', 'levels', {'in': 'tri'}, gamma=0.45)  # rounds the triangle's tip into an arch
    g.n('arched', 'directional_warp', {'in': 'ring', 'height': 'arch'}, intensity=0.12, angle=0.25)
    g.p('arch_height', 'arched.intensity', min=0.0, max=0.2)
    g.n('wave', 'fbm', scale_x=2, scale_y=2, octaves=3, roughness=0.35, seed=seed)
    g.n('wavy', 'directional_warp', {'in': 'arched', 'height': 'wave'}, intensity=0.03, angle=0.25)
    g.p('ring_waviness', 'wavy.intensity', min=0.0, max=0.05)
    g.p('ring_width', 'ring.width', min=0.1, max=0.8)
    g.n('fib', 'fbm', scale_x=4, scale_y=96, octaves=3, roughness=0.6, seed=seed + 7)
    g.n('grain', 'blend', {'fg': 'fib', 'bg': 'wavy'}, mode='overlay', opacity=0.3)
    g.p('fiber_strength', 'grain.opacity', min=0.0, max=1.0)
    return 'grain'


def quarter_sawn_grain(g, seed):
    """Quarter-sawn: tight straight rings with the medullary-ray flecks (short light streaks)."""
    g.n('ring', 'stripes', count=96, direction='v', width=0.4, softness=0.3)
    g.n('fib', 'fbm', scale_x=4, scale_y=128, octaves=3, roughness=0.6, seed=seed)
    g.n('rg', 'blend', {'fg': 'fib', 'bg': 'ring'}, mode='overlay', opacity=0.4)
    g.p('fiber_strength', 'rg.opacity')
    g.n('fl', 'fbm', scale_x=16, scale_y=64, octaves=3, roughness=0.5, seed=seed + 3)
    g.n('fleck', 'histogram_scan', {'in': 'fl'}, position=0.2, contrast=0.85)
    g.p('ray_flecks', 'fleck.position', min=0.0, max=0.5)
    g.n('grain', 'blend', {'fg': 'fleck', 'bg': 'rg'}, mode='screen', opacity=0.6)
    g.p('fleck_strength', 'grain.opacity')
    return 'grain'


def laminate_grain(g, seed):
    """Printed laminate: one short grain print repeated (visible repeats along each plank)."""
    base = wood_grain(g, rings=18, seed=seed, warp=0.03)
    g.n('print', 'transform', {'in': base}, tile=4)
    return 'print'


wood_plank_variant('wood_cathedral_oak', 'Flat-sawn oak planks with strong cathedral (arched) grain.', cathedral_grain, 4, 1, 'planks',
                   ((0.56, 0.36, 0.18), (0.40, 0.23, 0.10), (0.24, 0.12, 0.05)), 551)
wood_plank_variant('wood_quarter_sawn', 'Quarter-sawn oak: straight tight grain with silvery ray flecks.', quarter_sawn_grain, 6, 2, 'planks',
                   ((0.6, 0.42, 0.24), (0.45, 0.3, 0.15), (0.3, 0.18, 0.08)), 553, shift=(1 / 64, 2 / 64))
wood_plank_variant('wood_laminate', 'Laminate flooring: a printed wood decor that repeats every few planks, uniform tone, micro-bevel.',
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
    if painted:
        g.n('paint', 'uniform_color', color=col[0])
        g.p('paint_color', 'paint.color')
        g.n('shade', 'levels', {'in': 't.sampled'}, out_low=0.9, out_high=1.0)
        g.p('grain_show_through', 'shade.out_low', min=0.6, max=1.0)
        g.n('c0', 'blend', {'fg': 'shade', 'bg': 'paint'}, mode='multiply')
        r = rough_from(g, 't.sampled', 0.55, 0.45)
    else:
        c0 = wood_colors(g, 't.sampled', *col)
        r = rough_from(g, 't.sampled', 0.5, 0.4)
        g.n('c0', 'blend', {'fg': 't.random', 'bg': c0}, mode='overlay', opacity=0.4)
    g.n('sh', 'levels', {'in': prof}, out_low=0.8 if panel else 0.35, out_high=1.0)
    g.p('groove_shadow', 'sh.out_low', min=0.0, max=1.0)
    g.n('alb', 'blend', {'fg': 'sh', 'bg': 'c0'}, mode='multiply')
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
    wood = wood_colors(g, 't.sampled', (0.5, 0.33, 0.17), (0.36, 0.21, 0.09), (0.2, 0.1, 0.04))
    g.n('paint', 'uniform_color', color=[0.55, 0.62, 0.66])
    g.p('paint_color', 'paint.color')
    g.n('wn', 'fbm', scale_x=8, scale_y=8, octaves=6, roughness=0.6, seed=573)
    g.n('wm', 'blend', {'fg': 'wn', 'bg': 't.height'}, mode='multiply')
    g.n('keep', 'histogram_scan', {'in': 'wm'}, position=0.55, contrast=0.8)
    g.p('paint_left', 'keep.position', min=0.2, max=0.9)
    g.n('alb0', 'blend', {'fg': 'paint', 'bg': wood, 'mask': 'keep'})
    g.n('gapm', 'invert', {'in': 't.height'})
    g.n('gapc', 'uniform_color', color=[0.2, 0.17, 0.15])
    g.n('alb', 'blend', {'fg': 'gapc', 'bg': 'alb0', 'mask': 'gapm'}, mode='multiply')
    g.n('h', 'blend', {'fg': 'keep', 'bg': 't.height'}, mode='add', opacity=0.1)
    g.n('rough', 'levels', {'in': 'keep'}, out_low=0.75, out_high=0.45)
    g.p('roughness_wood', 'rough.out_low')
    g.p('roughness_paint', 'rough.out_high')
    finish(g, 'h', 'rough', 'alb', 0.005, normal_max=0.03, shift=(0.5, 1 / 12))


worn_painted_planks()


def wicker(name, desc, pattern, count, width, col, seed, holes=False):
    g = G(name, 'wood', desc)
    g.n('w', 'weave', count=count, pattern=pattern, width=width, seed=seed)
    g.p('strand_width', 'w.width', min=0.4 if holes else 0.7, max=1.0)
    g.n('fib', 'fbm', scale_x=count * 2, scale_y=count * 2, octaves=2, roughness=0.5, seed=seed + 1)
    g.n('hf', 'blend', {'fg': 'fib', 'bg': 'w.height'}, mode='overlay', opacity=0.15)
    g.n('tv', 'blend', {'fg': 'w.random', 'bg': 'hf'}, mode='overlay', opacity=0.4)
    g.p('strand_variation', 'tv.opacity')
    colors3(g, 'col', 'tv', [c * 0.45 for c in col], col, [min(1, c * 1.25) for c in col], 0.6, 'cane')
    if holes:  # cane webbing: the gaps between strands show what is behind (dark)
        g.n('hole', 'histogram_scan', {'in': 'w.height'}, position=0.8, contrast=0.9)
        g.p('hole_size', 'hole.position', min=0.5, max=1.0)
        g.n('bk', 'uniform_color', color=[0.03, 0.025, 0.02])
        g.p('behind_color', 'bk.color')
        g.n('alb', 'blend', {'fg': 'col', 'bg': 'bk', 'mask': 'hole'})
        alb = 'alb'
    else:
        alb = 'col'
    g.n('rough', 'levels', {'in': 'tv'}, out_low=0.55, out_high=0.35)
    g.p('roughness_min', 'rough.out_high')
    g.p('roughness_max', 'rough.out_low')
    finish(g, 'tv', 'rough', alb, 0.008, normal_max=0.06, shift=(0.5 / count, 0.5 / count))


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
        g.n('hb', 'blend', {'fg': 'bulge', 'bg': 'body'}, mode='multiply', opacity=0.6)
        g.p('stone_bulge', 'hb.opacity')
        body, rnd = 'body', 'cv'
    else:
        g.n('t', 'tile', layout='bricks', rows=rows, cols=cols, row_offset=0.5, gap=0.06, bevel=0.2, lum_var=0.6, seed=seed)
        g.p('mortar_width', 't.gap', min=0.0, max=0.2)
        g.p('edge_rounding', 't.bevel', min=0.02, max=0.4)
        body, rnd, hb = 't.height', 't.random', 't.height'
    g.n('f', 'fbm', scale_x=8, scale_y=8, octaves=7, roughness=0.6, seed=seed + 1)
    g.n('m', 'blend', {'fg': 'f', 'bg': rnd}, mode='overlay', opacity=0.6)
    g.p('stone_texture', 'm.opacity')
    colors3(g, 'col', 'm', [c * 0.55 for c in stone], stone, [min(1, c * 1.3) for c in stone], 0.5, 'stone')
    g.n('mc', 'uniform_color', color=mortar)
    g.p('mortar_color', 'mc.color')
    g.n('alb', 'blend', {'fg': 'col', 'bg': 'mc', 'mask': body})
    g.n('h', 'blend', {'fg': 'f', 'bg': 'hb' if irregular else hb}, mode='multiply', opacity=0.4)
    g.n('rough', 'levels', {'in': 'f'}, out_low=0.7, out_high=0.95)
    g.p('roughness_min', 'rough.out_low')
    g.p('roughness_max', 'rough.out_high')
    finish(g, 'h', 'rough', 'alb', 0.02, normal_max=0.1,
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
    g.n('p', 'voronoi', scale=96, jitter=1.0, mode='f1', seed=602)
    g.n('pm', 'histogram_scan', {'in': 'p'}, position=0.9, contrast=0.7)
    g.p('pore_amount', 'pm.position', min=0.8, max=1.0)
    g.n('s', 'blend', {'fg': 'pm', 'bg': 'f'}, mode='subtract', opacity=0.5)
    g.n('t', 'tile', {'pattern': 's'}, layout='bricks', rows=8, cols=2, row_offset=0.5, gap=0.05, bevel=0.04, lum_var=0.3, seed=603)
    g.p('joint_width', 't.gap', min=0.0, max=0.15)
    g.p('block_variation', 't.lum_var')
    g.n('m', 'blend', {'fg': 't.random', 'bg': 't.sampled'}, mode='overlay', opacity=0.4)
    colors3(g, 'col', 'm', [0.3, 0.3, 0.29], [0.45, 0.45, 0.43], [0.58, 0.58, 0.55], 0.5, 'block')
    g.n('mc', 'uniform_color', color=[0.5, 0.49, 0.46])
    g.p('mortar_color', 'mc.color')
    g.n('alb', 'blend', {'fg': 'col', 'bg': 'mc', 'mask': 't.height'})
    g.n('h', 'blend', {'fg': 't.sampled', 'bg': 't.height'}, mode='multiply', opacity=0.3)
    g.n('rough', 'levels', {'in': 'f'}, out_low=0.8, out_high=0.95)
    g.p('roughness_min', 'rough.out_low')
    g.p('roughness_max', 'rough.out_high')
    finish(g, 'h', 'rough', 'alb', 0.01, shift=(0.125, 1 / 16))


concrete_blocks()


def board_formed():
    g = G('concrete_board_formed', 'concrete', 'Board-formed concrete: the imprint of formwork boards (horizontal bands with wood grain) on grey concrete.')
    g.n('gr', 'fbm', scale_x=2, scale_y=64, octaves=4, roughness=0.6, seed=611)
    g.n('t', 'tile', {'pattern': 'gr'}, layout='planks', rows=8, cols=1, row_offset=0.9, gap=0.0, bevel=0.06, lum_var=0.4, seed=612)
    g.n('imp', 'blend', {'fg': 't.sampled', 'bg': 't.height'}, mode='multiply', opacity=0.5)
    g.p('grain_imprint', 'imp.opacity')
    g.n('f', 'fbm', scale_x=8, scale_y=8, octaves=6, roughness=0.6, seed=613)
    g.n('m', 'blend', {'fg': 'f', 'bg': 'imp'}, mode='overlay', opacity=0.5)
    g.n('m2', 'blend', {'fg': 't.random', 'bg': 'm'}, mode='overlay', opacity=0.3)
    g.p('board_tone_variation', 'm2.opacity')
    colors3(g, 'col', 'm2', [0.3, 0.3, 0.29], [0.48, 0.47, 0.45], [0.6, 0.59, 0.56], 0.5, 'concrete')
    g.n('rough', 'levels', {'in': 'f'}, out_low=0.75, out_high=0.92)
    g.p('roughness_min', 'rough.out_low')
    g.p('roughness_max', 'rough.out_high')
    finish(g, 'imp', 'rough', 'col', 0.006, shift=(0, 1 / 16))


board_formed()
cementish('concrete_exposed_aggregate', 'concrete', 'Exposed-aggregate / gravel concrete: dense small pebbles in a coarse grey matrix.', [0.45, 0.43, 0.4], 48, 128, (0.8, 0.95), 0.015, 621)
cementish('plaster_lime_rough', 'plaster', 'Rough lime plaster: coarse sand-float finish, warm white, uneven.', [0.78, 0.74, 0.66], 48, 128, (0.85, 0.97), 0.012, 631)
cementish('plaster_painted_red', 'plaster', 'Painted plaster wall in a strong colour, with trowel clouding and filled pores.', [0.5, 0.12, 0.08], 4, 48, (0.7, 0.85), 0.004, 633)

# ---------------------------------------------------------------- wallpaper motifs
def wallpaper_motif(name, desc, kind, col_a, col_b, seed):
    g = G(name, 'wallpaper', desc)
    if kind == 'dots':
        g.n('m1', 'shape', count=8, shape='disc', size=0.35, softness=0.04)
        g.p('dot_size', 'm1.size', min=0.1, max=0.7)
        g.n('m2', 'transform', {'in': 'm1'}, offset_u=1 / 16, offset_v=1 / 16)
        g.n('mot', 'blend', {'fg': 'm1', 'bg': 'm2'}, mode='max')
    elif kind == 'trellis':  # an ogee-like trellis: diagonal lines bent by a radial field
        g.n('d1', 'stripes', count=6, direction='diagonal', width=0.12, softness=0.03)
        g.n('d2', 'stripes', count=6, direction='antidiagonal', width=0.12, softness=0.03)
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
        g.n('tu', 'gradient_linear', direction='u', repeats=6, shape='triangle')
        g.n('tv', 'gradient_linear', direction='v', repeats=6, shape='triangle')
        g.n('dia', 'blend', {'fg': 'tu', 'bg': 'tv'}, mode='copy', opacity=0.5)
        g.n('ring', 'histogram_scan', {'in': 'dia'}, position=0.5, contrast=0.9)
        g.n('ring2', 'histogram_scan', {'in': 'dia'}, position=0.35, contrast=0.9)
        g.n('ir', 'invert', {'in': 'ring2'})
        g.n('mot', 'blend', {'fg': 'ir', 'bg': 'ring'}, mode='multiply')
        g.p('band_outer', 'ring.position', min=0.3, max=0.8)
        g.p('band_inner', 'ring2.position', min=0.05, max=0.45)
    g.n('ca', 'uniform_color', color=col_a)
    g.n('cb', 'uniform_color', color=col_b)
    g.p('ground_color', 'ca.color')
    g.p('motif_color', 'cb.color')
    g.n('m', 'blend', {'fg': 'cb', 'bg': 'ca', 'mask': 'mot'})
    g.n('paper', 'fbm', scale_x=64, scale_y=64, octaves=3, roughness=0.5, seed=seed)
    g.n('alb', 'blend', {'fg': 'paper', 'bg': 'm'}, mode='overlay', opacity=0.12)
    g.p('paper_texture', 'alb.opacity')
    g.n('h', 'blend', {'fg': 'mot', 'bg': 'paper'}, mode='add', opacity=0.2)
    g.n('rough', 'levels', {'in': 'mot'}, out_low=0.8, out_high=0.55)
    g.p('roughness_ground', 'rough.out_low')
    g.p('roughness_motif', 'rough.out_high')
    finish(g, 'h', 'rough', 'alb', 0.003)


wallpaper_motif('wallpaper_polka_dots', 'Polka-dot wallpaper: dots in a diagonal (half-drop) grid.', 'dots', [0.8, 0.78, 0.72], [0.2, 0.3, 0.45], 641)
wallpaper_motif('wallpaper_trellis', 'Trellis / ogee wallpaper: a lattice of curved diagonal lines.', 'trellis', [0.45, 0.55, 0.5], [0.85, 0.83, 0.76], 643)
wallpaper_motif('wallpaper_floral', 'Floral wallpaper: four-petal flowers in a half-drop repeat on a pale ground.', 'floral', [0.78, 0.74, 0.62], [0.55, 0.2, 0.25], 645)
wallpaper_motif('wallpaper_geometric', 'Geometric wallpaper: nested diamond bands in a regular lattice.', 'geometric', [0.12, 0.14, 0.18], [0.7, 0.6, 0.35], 647)

# ---------------------------------------------------------------- metal, plastic
def perforated_metal():
    g = G('metal_perforated', 'metal', 'Perforated metal sheet: round holes in a staggered grid, dark behind.')
    g.n('h1', 'shape', count=16, shape='disc', size=0.55, softness=0.06)
    g.n('h2', 'transform', {'in': 'h1'}, offset_u=1 / 32, offset_v=1 / 32)
    g.n('holes', 'blend', {'fg': 'h1', 'bg': 'h2'}, mode='max')
    g.p('hole_size', 'h1.size', min=0.2, max=0.9)
    g.n('sheet', 'invert', {'in': 'holes'})
    g.n('br', 'fbm', scale_x=2, scale_y=256, octaves=3, roughness=0.6, seed=651)
    colors3(g, 'col', 'br', [0.45, 0.45, 0.47], [0.58, 0.58, 0.6], [0.68, 0.68, 0.7], 0.5, 'metal')
    g.n('bk', 'uniform_color', color=[0.02, 0.02, 0.02])
    g.p('behind_color', 'bk.color')
    g.n('alb', 'blend', {'fg': 'col', 'bg': 'bk', 'mask': 'sheet'})
    g.n('rough', 'levels', {'in': 'br'}, out_low=0.3, out_high=0.45)
    g.p('roughness_min', 'rough.out_low')
    g.p('roughness_max', 'rough.out_high')
    g.n('metal', 'levels', {'in': 'sheet'}, out_low=0.0, out_high=1.0)
    g.p('sheet_metallic', 'metal.out_high')
    finish(g, 'sheet', 'rough', 'alb', 0.004, metallic='metal')


perforated_metal()


def tread_plate():
    g = G('metal_tread_plate', 'metal', 'Diamond (tread) plate: raised short bars alternating in direction on steel / aluminium.')
    g.n('d1', 'stripes', count=24, direction='diagonal', width=0.3, softness=0.3)
    g.n('d2', 'stripes', count=24, direction='antidiagonal', width=0.3, softness=0.3)
    g.n('sel', 'checker', count=6, softness=0.01)
    g.n('bars', 'blend', {'fg': 'd1', 'bg': 'd2', 'mask': 'sel'})
    g.n('cell', 'shape', count=12, shape='bell', size=0.8)
    g.n('h', 'blend', {'fg': 'cell', 'bg': 'bars'}, mode='multiply')
    g.n('br', 'fbm', scale_x=4, scale_y=4, octaves=4, roughness=0.5, seed=661)
    colors3(g, 'col', 'br', [0.5, 0.5, 0.52], [0.62, 0.62, 0.64], [0.72, 0.72, 0.74], 0.5, 'metal')
    g.n('rough', 'levels', {'in': 'br'}, out_low=0.25, out_high=0.45)
    g.p('roughness_min', 'rough.out_low')
    g.p('roughness_max', 'rough.out_high')
    g.n('metal', 'uniform_gray', value=1.0)
    g.p('metallic', 'metal.value')
    finish(g, 'h', 'rough', 'col', 0.01, metallic='metal', shift=(1 / 48, 1 / 48))


tread_plate()


def woven_vinyl():
    g = G('plastic_woven_vinyl', 'plastic', 'Woven vinyl flooring: flat two-colour PVC strands in a basket weave, semi-gloss.')
    g.n('w', 'weave', count=48, pattern='basket_2_2', width=0.92, seed=671)
    g.p('strand_width', 'w.width', min=0.7, max=1.0)
    g.n('ca', 'uniform_color', color=[0.3, 0.3, 0.28])
    g.n('cb', 'uniform_color', color=[0.55, 0.53, 0.48])
    g.p('warp_color', 'ca.color')
    g.p('weft_color', 'cb.color')
    g.n('cm', 'blend', {'fg': 'ca', 'bg': 'cb', 'mask': 'w.warp'})
    g.n('fl', 'levels', {'in': 'w.height'}, in_low=0.3, in_high=0.9)
    g.n('sh', 'levels', {'in': 'fl'}, out_low=0.6, out_high=1.0)
    g.p('shadowing', 'sh.out_low', min=0.2, max=1.0)
    g.n('alb', 'blend', {'fg': 'sh', 'bg': 'cm'}, mode='multiply')
    g.n('rough', 'levels', {'in': 'fl'}, out_low=0.6, out_high=0.35)
    g.p('roughness_min', 'rough.out_high')
    g.p('roughness_max', 'rough.out_low')
    finish(g, 'fl', 'rough', 'alb', 0.003)


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
