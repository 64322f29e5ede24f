"""Shared settings of the side-by-side benchmark (jaderender vs Mitsuba 3) in this folder.

Everything comes from environment variables, with defaults relative to this file:
  JADERENDER  our binary (a copy of the project's build/jaderender)   [required]
  REF_DIR     reference scenes              (default: the repository's data/reference)
  ANCHOR_DIR  folder of scenes.py (Mitsuba scene definitions)   (default: this folder)
  MAIN_DIR    project checkout (demo data)  (default: this repository)
  PERF_WORK   scratch folder for big images (default $TMPDIR/perf_work)
  DRJIT_LIBLLVM_PATH  LLVM 19 for drjit's llvm variants (/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1 after apt-get install libllvm19)
"""
import os, sys, subprocess, time, tempfile
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
REF_DIR = os.environ.get('REF_DIR', os.path.join(HERE, '..', '..', 'data', 'reference'))
ANCHOR_DIR = os.environ.get('ANCHOR_DIR', HERE)
MAIN_DIR = os.environ.get('MAIN_DIR', os.path.join(HERE, '..', '..'))
WORK = os.environ.get('PERF_WORK', os.path.join(tempfile.gettempdir(), 'perf_work'))
os.makedirs(WORK, exist_ok=True)


def jaderender():
    b = os.environ.get('JADERENDER')
    if not b:
        sys.exit('set JADERENDER to a copy of build/jaderender')
    return b


def loadavg():
    return open('/proc/loadavg').read().split()[0]


CAM = {'A': '0,0,4', 'B': '0,0,4', 'C': '0,0,2.4'}


def scene_args(scene):
    """jaderender render flags for reference scenes A, B, C (directional light off)."""
    common = ['--camera-origin', CAM[scene], '--camera-target', '0,0,0', '--camera-up', '0,1,0',
              '--fov', '40', '--width', '256', '--height', '256', '--env', '1',
              '--light-irradiance', '0']
    if scene in 'AB':
        # The unit sphere as Mitsuba renders it: analytic (unit_sphere.obj is its
        # tessellation).
        a = ['--sphere', '0,0,0,1', '--sigma-s', '3.8,7.2,9.6',
             '--sigma-a', '0.2,0.8,2.4']
        a += ['--boundary', 'none'] if scene == 'A' else ['--boundary', 'fresnel', '--ior', '1.6']
    else:
        a = ['--mesh', os.path.join(REF_DIR, 'blob.obj'), '--flat',
             '--volume', os.path.join(REF_DIR, 'sceneC_medium.vdb'), '--boundary', 'fresnel', '--ior', '1.6']
    return a + common


def _mi_scalar():
    import mitsuba as mi
    if mi.variant() is None:
        mi.set_variant('scalar_rgb')
    return mi


def read_img(path):
    mi = _mi_scalar()
    a = np.array(mi.Bitmap(path), dtype=np.float64)
    return a[..., :3]


def write_img(path, a):
    mi = _mi_scalar()
    mi.Bitmap(np.ascontiguousarray(a, dtype=np.float32)).write(path)


def reference(scene, ref_dir=None):
    d = ref_dir or REF_DIR
    return read_img(os.path.join(d, f'scene{scene}_ref.exr')), read_img(os.path.join(d, f'scene{scene}_var.exr'))


def rmse_floor_corrected(img, ref, var):
    mse = np.mean((img - ref) ** 2)
    return float(np.sqrt(max(mse - np.mean(var), 0.0))), float(np.sqrt(mse))


def run_ours(scene, out, spp, seed=1, threads=2, extra=(), reference_exr=None, timeout=None):
    """Runs one render; returns dict(wall, cpu, stdout, csv rows)."""
    cmd = [jaderender(), 'render'] + scene_args(scene) + ['--spp', str(spp), '--seed', str(seed),
                                                          '--threads', str(threads), '--out', out, '--png', '']
    conv = out[:-4] + '_conv.csv'
    cmd += ['--convergence', conv]
    if reference_exr:
        cmd += ['--reference', reference_exr]
    cmd += list(extra)
    t0 = time.perf_counter()
    r0 = os.times()
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    r1 = os.times()
    wall = time.perf_counter() - t0
    if p.returncode != 0:
        raise RuntimeError(p.stderr[-2000:])
    rows = []
    if os.path.exists(conv):
        import csv
        rows = list(csv.DictReader(open(conv)))
    return dict(wall=wall, cpu=(r1.children_user - r0.children_user) + (r1.children_system - r0.children_system),
                stdout=p.stdout, rows=rows, cmd=cmd)
