"""Relative MSE per pixel of the light estimators from pairs of renders.

Two independent renders a, b of one image have E[(a - b)^2] = 2 Var, so the
relative MSE of one render is the mean over covered pixels of
(a - b)^2 / 2 / m^2, m = (a + b) / 2, on the mean of the three channels
(pixels darker than 1e-4 left out); with several pairs (seeds 1–2, 3–4,
...) it prints each pair's and their mean, and for each light the ratio
of disc hits' (off) mean to each estimator's. Usage:
light_race.py RUNS PAIRS RADIUS...
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
    """Samples per pixel on average (a pass cut by the time budget leaves
    some pixels a sample short: the log gives the fewest and the mean)."""
    text = open(log_path).read()
    found = re.findall(r"([\d.]+) on average\) in|(\d+) spp in", text)
    return found[-1][0] or found[-1][1] if found else "?"


def rel_mse(stem, first):
    a, b = load(f"{stem}{first}.exr"), load(f"{stem}{first + 1}.exr")
    covered = (a[..., 3] > 0.5) & (b[..., 3] > 0.5)
    la, lb = a[..., :3].mean(-1)[covered], b[..., :3].mean(-1)[covered]
    m = 0.5 * (la + lb)
    lit = m > 1e-4
    return np.mean((la - lb)[lit] ** 2 / 2 / m[lit] ** 2)


runs, pairs = sys.argv[1], int(sys.argv[2])
rows = [(f"{r}°", f"r{r}", e) for r in sys.argv[3:] for e in ["off", "cone", "manifold", "manifold2", "guided"]]
rows += [("sky", "sky", e) for e in ["off", "auto", "auto2"]]
print(f"{'light':>6} {'estimator':>9} {'rel. MSE':>9} {'off/this':>8} {'spp':>9}  per pair")
off = {}
for label, case, estimator in rows:
    stem = f"{runs}/{case}_{estimator}_s"
    per_pair = [rel_mse(stem, 2 * k + 1) for k in range(pairs)]
    mean = float(np.mean(per_pair))
    if estimator == "off":
        off[case] = mean
    counts = [round(float(n)) for n in (spp(f"{stem}{seed}.log") for seed in range(1, 2 * pairs + 1)) if n != "?"]
    spread = f"{min(counts)}-{max(counts)}" if counts else "?"
    print(f"{label:>6} {estimator:>9} {mean:9.5f} {off[case] / mean:8.1f} {spread:>9}  "
          + " ".join(f"{v:.5f}" for v in per_pair))
