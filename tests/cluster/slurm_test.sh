#!/usr/bin/env bash
# The Slurm scripts on a real, one-node Slurm started on this machine
# (scripts/slurm/local-cluster.sh): a render split into 4 pieces, one of
# which fails once and is run again by Slurm, merged by the dependent job and
# compared with a single-process render pixel for pixel (bit for bit); and a
# manifest of 3 fits run as an array job, then summarised.
#
#   tests/cluster/slurm_test.sh JADERENDER
#
# Fails, saying why, when the daemons cannot start.
set -euo pipefail
jade=$(readlink -f "$1")
root=$(cd "$(dirname "$0")/../.." && pwd)
data=$root/data
work=$(mktemp -d /tmp/jade-slurm-XXXXXX)
cluster=$work/cluster

cleanup() {
  "$root/scripts/slurm/local-cluster.sh" stop "$cluster" || true
  rm -rf "$work"
}
trap cleanup EXIT

say() { echo "slurm_test: $*"; }
fail() { say "FAILED: $*"; for f in "$work"/run/*.log; do [ -f "$f" ] && { echo "--- $f"; tail -n 5 "$f"; }; done; exit 1; }

conf=$("$root/scripts/slurm/local-cluster.sh" start "$cluster") || fail "the local Slurm did not start (see above)"
eval "$conf"
say "one-node Slurm up: $(sinfo -h -o '%P %D nodes, %c CPUs, %T')"

mkdir -p "$work/run"
cd "$work/run"

# --- a split render -----------------------------------------------------------
cat >job.json <<JOB
{"scene": {"mesh": "$data/reference/blob.obj", "boundary": "fresnel"},
 "medium": {"sigma_s": [4, 6, 8], "sigma_a": [0.2, 0.4, 1.0]},
 "camera": {"width": 96, "height": 80},
 "lights": {"environment": "0.2,0.3,0.4"},
 "settings": {"spp": 37, "seed": 9},
 "outputs": {"out": "single.exr"}}
JOB
"$jade" render --job job.json >/dev/null || fail "the single-process render failed"

# Piece 1 of 4 crashes on its first run, as a task on a failing node would;
# Slurm must run it again and the merge must still be exact.
cat >flaky-jaderender <<FLAKY
#!/usr/bin/env bash
if [[ " \$* " == *" 1/4 "* ]] && [ ! -f "$work/run/crashed-once" ]; then
  touch "$work/run/crashed-once"; echo "flaky-jaderender: simulated crash" >&2; exit 9
fi
exec "$jade" "\$@"
FLAKY
chmod +x flaky-jaderender
JADERENDER=$work/run/flaky-jaderender "$root/scripts/slurm/split-render.sh" --job job.json --pieces 4 \
  --out split.exr -- --cpus-per-task=1 || fail "split-render.sh did not submit"

# --- a batch of fits ----------------------------------------------------------
photo=$data/photos/ambientcg_Onyx002_512_diff.jpg
cat >fits.json <<MANIFEST
{"flags": ["--resolution", "16", "--width", "48", "--height", "48", "--spp", "8", "--fit", "bisect",
           "--fit-width", "24", "--fit-spp", "16", "--fit-max-renders", "3"],
 "entries": [{"photo": "$photo", "mesh": "$data/reference/blob.obj", "out": "fit-blob"},
             {"photo": "$photo", "mesh": "$data/meshes/spot-cow.obj", "out": "fit-cow"},
             {"photo": "$photo", "mesh": "$data/reference/unit_sphere.obj", "out": "fit-sphere", "flags": ["--match", "per-channel"]}]}
MANIFEST
JADERENDER=$jade "$root/scripts/slurm/batch.sh" fits.json -- --cpus-per-task=1 || fail "batch.sh did not submit"

# --- wait (the crashed piece waits out Slurm's requeue delay, cred_expire) ---
for _ in $(seq 1 400); do
  [ -z "$(squeue -h)" ] && break
  sleep 1
done
[ -z "$(squeue -h)" ] || fail "jobs still queued after 400 s: $(squeue -h | tr '\n' ';')"

[ -f crashed-once ] || fail "the flaky piece never ran"
grep -q "Slurm runs it again" jade-piece-*_1.log || fail "the failed piece was not given back to Slurm"
[ -f split.exr ] || fail "the merge job wrote no split.exr"
idiff -fail 0 -failpercent 0 -warn 0 single.exr split.exr >/dev/null ||
  fail "the merged image differs from the single-process render"
say "split render: 4 pieces (one crashed and re-run by Slurm) merged; pixels bit-identical to one render"

for d in fit-blob fit-cow fit-sphere; do
  [ -f "$d/report.json" ] || fail "$d/report.json is missing"
done
[ "$(grep -c ',done,' summary.csv)" = 3 ] || fail "summary.csv does not list 3 fits done: $(cat summary.csv)"
[ -f contact-sheet.png ] || fail "no contact sheet"
say "batch: 3 fits through an array job, summary.csv and contact-sheet.png written"
say "passed"
