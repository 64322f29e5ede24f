"""Mitsuba 3 as a third witness on a jaderender volume: renders the scene of
the pipeline's report.json (index-matched boundary, constant environment,
no sun: the set-up scripts/bench-witness.sh makes) with the grids from
vdb_to_vol.py, two seeds, and prints the object pixels' mean per channel for
every renderer whose two renders are in WORK (ours, cycles, mitsuba), with the
standard error from the two seeds' differences and the difference to ours.
Usage: witness_volume.py OUTPUT_FOLDER WORK_FOLDER SPP"""
import json
import os
import sys
import time

import mitsuba as mi
import numpy as np

src, work, spp = sys.argv[1], sys.argv[2], int(sys.argv[3])
mi.set_variant('llvm_ad_rgb')
job = json.load(open(os.path.join(src, 'report.json')))['job']
cam, g = job['camera'], job['scene']['g']
box = json.load(open(os.path.join(work, 'bbox.json')))
bmin, bmax = np.array(box['bmin']), np.array(box['bmax'])
T = mi.ScalarTransform4f
to_world = T().translate(bmin.tolist()) @ T().scale((bmax - bmin).tolist())
grid = lambda name: {'type': 'gridvolume', 'filename': os.path.join(work, name), 'filter_type': 'trilinear',
                     'wrap_mode': 'clamp', 'to_world': to_world}
env = float(job['lights']['environment']) * float(job['lights']['environment_scale'])
scene = mi.load_dict({
    'type': 'scene',
    'integrator': {'type': 'volpath', 'max_depth': -1},
    'env': {'type': 'constant', 'radiance': {'type': 'rgb', 'value': [env] * 3}},
    'sensor': {'type': 'perspective', 'fov': cam['fov_degrees'], 'fov_axis': 'x',
               'to_world': T().look_at(origin=cam['origin'], target=cam['target'], up=cam['up']),
               'sampler': {'type': 'independent', 'sample_count': spp},
               'film': {'type': 'hdrfilm', 'width': cam['width'], 'height': cam['height'],
                        'rfilter': {'type': 'box'}, 'pixel_format': 'rgba', 'component_format': 'float32'}},
    'medium': {'type': 'heterogeneous', 'sigma_t': grid('sigma_t.vol'), 'albedo': grid('albedo.vol'), 'scale': 1.0,
               'phase': {'type': 'hg', 'g': g} if g != 0 else {'type': 'isotropic'}},
    'shape': {'type': 'obj', 'filename': os.path.join(work, 'mesh.obj'), 'bsdf': {'type': 'null'},
              'interior': {'type': 'ref', 'id': 'medium'}},
})
start = time.time()
for seed in (1, 2):
    mi.util.write_bitmap(os.path.join(work, f'mitsuba{seed}.exr'), mi.render(scene, spp=spp, seed=seed),
                         write_async=False)
print('mitsuba: %d spp, two seeds in %.1f s' % (spp, time.time() - start))

load = lambda p: np.array(mi.Bitmap(p), dtype=np.float64)[..., :3]
mask = np.array(mi.Bitmap(os.path.join(work, 'coverage.exr')))[..., 3] >= 0.5


def means(name):
    a, b = load(os.path.join(work, name + '1.exr'))[mask], load(os.path.join(work, name + '2.exr'))[mask]
    return 0.5 * (a + b).mean(0), np.sqrt(((a - b) ** 2).sum(0) / 4.0) / mask.sum()


ours = means('ours')
print('object pixels: %d' % mask.sum())
print('%-8s mean (R, G, B)            std. error             vs jaderender' % '')
for name in ('ours', 'mitsuba', 'cycles'):
    if not os.path.exists(os.path.join(work, name + '2.exr')):
        continue
    m, e = means(name)
    rel = 100 * (m / ours[0] - 1)
    print('%-8s %s  %s  %s %%' % (name, np.round(m, 4), np.round(e, 4), np.round(rel, 2)))
