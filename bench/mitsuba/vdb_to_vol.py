"""Turns a jaderender pipeline output folder into Mitsuba 3 inputs: the .vdb's
sigma_s and sigma_a grids as sigma_t.vol and albedo.vol (Mitsuba's gridvolume,
cell-centred, on the grids' active box), and the mesh of preview.glb (world
coordinates, as jaderender renders it) as mesh.obj. Run with Debian's python3
(python3-openvdb). Usage: vdb_to_vol.py OUTPUT_FOLDER WORK_FOLDER"""
import json
import os
import struct
import sys

import numpy as np
import pyopenvdb as vdb

src, work = sys.argv[1], sys.argv[2]
ss = vdb.read(os.path.join(src, 'volume.vdb'), 'sigma_s')
sa = vdb.read(os.path.join(src, 'volume.vdb'), 'sigma_a')
lo, hi = ss.evalActiveVoxelBoundingBox()
n = [hi[i] - lo[i] + 1 for i in range(3)]
A = np.zeros((n[0], n[1], n[2], 3), np.float32)
B = np.zeros_like(A)
ss.copyToArray(A, ijk=lo)
sa.copyToArray(B, ijk=lo)
st = A + B
active = st.max(axis=3) > 0
albedo = np.where(st > 0, A / np.maximum(st, 1e-30), 0).astype(np.float32)
# Mitsuba interpolates σ_t and the albedo separately and multiplies them: at
# the edge of the masked grids (zero beyond the mesh's interior grown by one
# voxel) that would thin σ_s twice and thicken σ_a, where jaderender (and
# Cycles) interpolate σ_s and σ_a. So the voxels beyond the mask take their
# active neighbours' mean (σ_t is the same everywhere in a d_a = 1 volume).
for _ in range(4):
    total = np.zeros_like(st)
    albedo_total = np.zeros_like(albedo)
    count = np.zeros(active.shape, np.float32)
    for axis in range(3):
        for shift in (-1, 1):
            nb = np.roll(active, shift, axis)
            total += np.where(nb[..., None], np.roll(st, shift, axis), 0)
            albedo_total += np.where(nb[..., None], np.roll(albedo, shift, axis), 0)
            count += nb
    fill = ~active & (count > 0)
    st[fill] = total[fill] / count[fill][..., None]
    albedo[fill] = albedo_total[fill] / count[fill][..., None]
    active |= fill
vs = np.array(ss.transform.voxelSize())
origin = np.array(ss.transform.indexToWorld(lo))
# Mitsuba's voxel i is centred at (i + 0.5)/n of its box; OpenVDB's at origin + i*voxel.
bmin, bmax = origin - 0.5 * vs, origin + (np.array(n) - 0.5) * vs


def write_vol(path, data):  # data [x, y, z, c]; .vol v3 holds [z, y, x, c]
    d = np.ascontiguousarray(np.transpose(data, (2, 1, 0, 3)), dtype='<f4')
    with open(path, 'wb') as fh:
        fh.write(b'VOL' + np.uint8(3).tobytes() + np.int32(1).tobytes())
        fh.write(np.array([n[0], n[1], n[2], 3], '<i4').tobytes())
        fh.write(np.array(list(bmin) + list(bmax), '<f4').tobytes())
        fh.write(d.tobytes())


os.makedirs(work, exist_ok=True)
write_vol(os.path.join(work, 'sigma_t.vol'), st)
write_vol(os.path.join(work, 'albedo.vol'), albedo)
json.dump({'bmin': bmin.tolist(), 'bmax': bmax.tolist()}, open(os.path.join(work, 'bbox.json'), 'w'))

# preview.glb as jaderender writes it: accessor 0 positions, 2 indices, one buffer.
b = open(os.path.join(src, 'preview.glb'), 'rb').read()
json_len = struct.unpack('<I', b[12:16])[0]
gltf = json.loads(b[20:20 + json_len])
bin_at = 20 + json_len + 8


def accessor(i, dtype):
    view = gltf['bufferViews'][gltf['accessors'][i]['bufferView']]
    start = bin_at + view.get('byteOffset', 0)
    return np.frombuffer(b[start:start + view['byteLength']], dtype).reshape(-1, 3)


with open(os.path.join(work, 'mesh.obj'), 'w') as fh:
    for p in accessor(0, '<f4'):
        fh.write('v %.9g %.9g %.9g\n' % tuple(p))
    for f in accessor(2, '<u4'):
        fh.write('f %d %d %d\n' % tuple(f + 1))
print('vdb_to_vol: %d active voxels, box %s..%s' % (ss.activeVoxelCount(), bmin.round(4), bmax.round(4)))
