#!/usr/bin/env bash
# The light estimators through the boundary at equal time (README, "How the
# lights reach the inside"): the demo's volume in the vase, 256², for each
# light radius and each --light-nee without the light guide (and the walk with
# --light-chain 2), and the default with the guide (guided), and
# under Blender's sunrise HDR (light off) with the environment's walk off, on,
# and on with both chains; `pairs` pairs of seeds each (1: seeds 1 and 2; 3:
# seeds 1–6); prints the relative MSE per pixel from each pair's difference,
# and their mean over the pairs: one pair's figure moves by about 10 % with
# the seeds (a few dark pixels of the vase's neck and foot hold much of it).
#   bash scripts/light-race.sh [seconds] [radii] [pairs]   (default: 30 "20 5" 1; "" for the sky alone)
# The sky renders are transparent: their MSE is over the object's pixels only.
# The discs shine from the direction every figure of this race was measured
# with (0.35,0.8,0.5, the default before the default became a delta light
# near the camera's view), whatever the job's own light.
# Runs the demo first when out/onyx002/report.json is missing.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-30}
radii=${2-20 5}
pairs=${3:-1}
seeds=$(seq 1 $((2 * pairs)))

bash scripts/setup.sh
source scripts/bench-venv.sh
job=out/onyx002/report.json
if [ ! -e "$job" ]; then
    mkdir -p out
    build/jaderender --photo data/photos/ambientcg_Onyx002_512_diff.jpg \
        --mesh data/meshes/greek-vase-01.glb --out out/onyx002
fi
runs=$work/light-race
mkdir -p "$runs"
cp build/jaderender "$work/jaderender"
# Without the light guide: disc hits only, the cone, the walk, the walk with
# the second chain; then the default (auto, with the guide).
for r in $radii; do
    for e in off cone manifold manifold2 guided; do
        case $e in
            guided) flags=(--light-nee auto --light-chain auto --light-guide true) ;;
            manifold2) flags=(--light-nee manifold --light-chain 2 --light-guide false) ;;
            *) flags=(--light-nee "$e" --light-chain 1 --light-guide false) ;;
        esac
        for seed in $seeds; do
            "$work/jaderender" render --job "$job" --width 256 --height 256 --spp 1000000 \
                --time "$seconds" --light-radius "$r" --light-dir 0.35,0.8,0.5 --seed "$seed" "${flags[@]}" \
                --out "$runs/r${r}_${e}_s${seed}.exr" --png "" --convergence "" \
                > "$runs/r${r}_${e}_s${seed}.log"
        done
    done
done
for e in off auto auto2; do
    for seed in $seeds; do
        "$work/jaderender" render --job "$job" --width 256 --height 256 --spp 1000000 \
            --time "$seconds" --light-irradiance 0 --env data/hdri/blender_sunrise.exr --transparent \
            --light-nee "${e%2}" --seed "$seed" --light-chain "$([ "$e" = auto2 ] && echo 2 || echo 1)" \
            --out "$runs/sky_${e}_s${seed}.exr" --png "" --convergence "" \
            > "$runs/sky_${e}_s${seed}.log" 2>&1
    done
done
"$work/venv/bin/python" bench/light_race.py "$runs" "$pairs" $radii
