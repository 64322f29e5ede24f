"""Relative MSE per pixel of the light estimators from pairs of renders.

Two independent renders a, b of one image have E[(a - b)^2] = 2 Var, so the
relative MSE of one render is the mean over covered pixels of
(a - b)^2 / 2 / m^2, m = (a + b) / 2, on the mean of the three channels
(pixels darker than 1e-4 left out). Usage: light_race.py RUNS RADIUS...
Rows: each radius with --light-nee off, cone and manifold, and manifold with
--light-chain 2 (manifold2), all without the light guide, and the default
with it (guided) (files r<radius>_<estimator>_s<seed>), then the
sunrise sky with off, auto, and auto with --light-chain 2 (auto2)
(sky_<estimator>_s<seed>).
"""
import re
import sys

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_rgb")


def load(path):
    return np.array(mi.Bitmap(path), dtype=np.float64)


def spp(log_path):
    found = re.findall(r"(\d+) spp in", open(log_path).read())
    return found[-1] if found else "?"


def rel_mse(stem):
    a, b = load(stem + "1.exr"), load(stem + "2.exr")
    covered = (a[..., 3] > 0.5) & (b[..., 3] > 0.5)
    la, lb = a[..., :3].mean(-1)[covered], b[..., :3].mean(-1)[covered]
    m = 0.5 * (la + lb)
    lit = m > 1e-4
    return np.mean((la - lb)[lit] ** 2 / 2 / m[lit] ** 2)


runs = sys.argv[1]
rows = [(f"{r}°", f"r{r}", e) for r in sys.argv[2:] for e in ["off", "cone", "manifold", "manifold2", "guided"]]
rows += [("sky", "sky", e) for e in ["off", "auto", "auto2"]]
print(f"{'light':>6} {'estimator':>9} {'rel. MSE':>9} {'spp':>6}")
for label, case, estimator in rows:
    stem = f"{runs}/{case}_{estimator}_s"
    print(f"{label:>6} {estimator:>9} {rel_mse(stem):9.4f} {spp(stem + '1.log'):>6}")
