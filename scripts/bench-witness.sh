#!/usr/bin/env bash
# Three renderers on one fitted volume (docs/blender.md, "A fitted volume"):
# the pipeline writes the demo photo's volume at 64³ in the vase with the
# given k_s and contrast (default: the demo's fit), index-matched, under a
# constant environment of 1 and no sun; jaderender, Cycles (the pipeline's
# blender.py, Debian's Blender) and Mitsuba 3 (bench-work/venv) each render it
# twice (seeds 1 and 2), and the object pixels' means are printed side by side.
# Usage: bash scripts/bench-witness.sh [KS] [CONTRAST] [SPP]
set -euo pipefail
cd "$(dirname "$0")/.."
ks=${1:-2.30,0.92,0.07}
contrast=${2:-1.7,6.1,11.2}
spp=${3:-512}
source scripts/bench-venv.sh
dpkg-query -W -f='${Status}' python3-openvdb 2>/dev/null | grep -q "install ok installed" ||
    sudo_if_needed apt-get install -y -qq python3-openvdb < /dev/null
w=$work/witness
rm -rf "$w" && mkdir -p "$w"
build/jaderender --photo data/photos/ambientcg_Onyx002_512_diff.jpg --mesh data/meshes/greek-vase-01.glb \
    --resolution 64 --fit none --ks "$ks" --contrast "$contrast" --boundary none --env 1 --light-irradiance 0 \
    --width 128 --height 128 --spp "$spp" --exposure 1 --out "$w/o" > /dev/null
for seed in 1 2; do
    build/jaderender render --job "$w/o/report.json" --seed $seed --spp "$spp" --out "$w/ours$seed.exr" \
        --png '' --convergence '' > /dev/null
    blender -b --python "$w/o/blender.py" -- --exr "$w/cycles$seed.exr" --samples "$spp" --seed $seed > "$w/blender$seed.log" 2>&1
done
build/jaderender render --job "$w/o/report.json" --transparent --spp 16 --out "$w/coverage.exr" \
    --png '' --convergence '' > /dev/null
/usr/bin/python3 bench/mitsuba/vdb_to_vol.py "$w/o" "$w"
"$work/venv/bin/python" bench/mitsuba/witness_volume.py "$w/o" "$w" "$spp"
