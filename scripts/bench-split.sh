#!/usr/bin/env bash
# Split rendering on this machine (README, "Rendering on a cluster"): the
# demo's fitted 256³ volume in the vase, 512², as one process and as 1, 2 and
# 4 pieces run at once (`render --piece I/N`, one thread each), then merged.
# Prints wall times, the speed-up over one single-threaded piece, what each
# piece spends before rendering (process start, mesh and volume loading) and
# the merge's own cost; checks the merge against the single render.
#   bash scripts/bench-split.sh [spp]        (default 64)
# Runs the demo first when out/onyx002/report.json is missing.
set -euo pipefail
cd "$(dirname "$0")/.."
spp=${1:-64}

bash scripts/setup.sh >/dev/null
job=out/onyx002/report.json
if [ ! -e "$job" ]; then
    mkdir -p out
    build/jaderender --photo data/photos/ambientcg_Onyx002_512_diff.jpg \
        --mesh data/meshes/greek-vase-01.glb --out out/onyx002
fi
work=bench-work/split
rm -rf "$work"
mkdir -p "$work"
jade=build/jaderender
now() { date +%s.%N; }
elapsed() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.2f", b - a }'; }

t0=$(now)
"$jade" render --job "$job" --spp "$spp" --out "$work/single.exr" >"$work/single.log" 2>/dev/null
t1=$(now)
echo "one process, all $(nproc) cores: $(elapsed "$t0" "$t1") s"

start=$(now)
"$jade" --version >/dev/null
echo "process start-up (--version): $(elapsed "$start" "$(now)") s"

base=""
for n in 1 2 4; do
    start=$(now)
    for ((i = 0; i < n; i++)); do
        "$jade" render --job "$job" --spp "$spp" --out "$work/split$n.exr" --piece "$i/$n" --threads 1 \
            >"$work/piece$n-$i.log" 2>/dev/null &
    done
    wait
    end=$(now)
    wall=$(elapsed "$start" "$end")
    [ -z "$base" ] && base=$wall
    loads=$(grep -h "loading" "$work"/piece$n-*.log | sed 's/.*loading \([0-9.]*\) s, .*peak memory \(.*\)/\1 s (peak \2)/' | paste -sd ',' -)
    start=$(now)
    "$jade" merge "$work"/split$n.part-*.exr --out "$work/split$n.exr" >"$work/merge$n.log"
    merge=$(elapsed "$start" "$(now)")
    same=$(idiff -fail 0 -failpercent 0 -warn 0 "$work/single.exr" "$work/split$n.exr" >/dev/null && echo "bit-identical" || echo "DIFFERS")
    size=$(du -ch "$work"/split$n.part-*.exr | tail -n 1 | cut -f 1)
    echo "$n piece(s) at once, 1 thread each: $wall s wall, speed-up $(awk -v a="$base" -v b="$wall" 'BEGIN { printf "%.2f", a / b }')x" \
         "over one piece; loading per piece: $loads; merge $merge s (pieces on disk $size); $same"
done
