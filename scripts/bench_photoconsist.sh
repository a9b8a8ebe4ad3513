#!/usr/bin/env bash
# Benchmark of the photoconsist stage on a synthetic scene with dinoRing's cameras
# (48 views, 640 x 480): runs photoconsist + refine level by level, then the scores pass,
# and writes one JSON record per run of photoconsist (faces tested, lattice points, points
# scored, crossing faces, recall/precision against the ground truth, seconds, peak memory).
#
#   scripts/bench_photoconsist.sh [OUT_JSON] [WORK_DIR]
# Environment: BUILD_DIR (default build), OBJECT (default torus), LEVELS (default: as many
# as bcc-init --print-levels says), THREADS (default: all cores), EXTRA (extra photoconsist
# arguments, e.g. "--set photo.T=0.9"). The scene is rendered once into WORK_DIR/scene.
# CPU seconds (user + system), wall seconds and peak RSS come from /usr/bin/time.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)
OUT_JSON=${1:-bench_photoconsist.json}
WORK=${2:-/tmp/tetmvs_bench_photoconsist}
BUILD_DIR=${BUILD_DIR:-build}
BIN=$ROOT/$BUILD_DIR/bin
OBJECT=${OBJECT:-torus}
THREADS=${THREADS:-0}
EXTRA=${EXTRA:-}
PAR=$ROOT/../shared/data/middlebury/dinoRing/dinoR_par.txt
[ -f "$PAR" ] || PAR=$ROOT/data/middlebury/dinoRing/dinoR_par.txt
for p in synth ingest bcc-init refine photoconsist; do
  [ -x "$BIN/$p" ] || { echo "bench_photoconsist: $BIN/$p not built" >&2; exit 1; }
done
[ -f "$PAR" ] || { echo "bench_photoconsist: dinoRing par file not found ($PAR)" >&2; exit 1; }

SCENE=$WORK/scene
mkdir -p "$WORK"
if [ ! -f "$SCENE/scene.h5" ]; then
  "$BIN/synth" -q --object "$OBJECT" --cameras "$PAR" --out "$SCENE"
  "$BIN/ingest" -q "$SCENE" -o "$SCENE/scene.h5"
fi
"$BIN/bcc-init" -q --scene "$SCENE/scene.h5" --out "$WORK/mesh_0.h5"
LEVELS=${LEVELS:-$("$BIN/bcc-init" -q --scene "$SCENE/scene.h5" --print-levels 2>/dev/null | tail -1)}

RECORDS=$WORK/records.txt
: > "$RECORDS"
run() {  # run LABEL CMD... : appends "LABEL<TAB>summary line cpu_seconds=... wall_seconds=..." to RECORDS
  local label=$1; shift
  local log tm
  tm=$(mktemp)
  log=$(/usr/bin/time -f "%U %S %e %M" -o "$tm" "$@" --threads "$THREADS" -q 2>&1 | tail -1)
  log="$log $(awk '{printf "cpu_seconds=%.2f wall_seconds=%.2f maxrss_mb=%.1f", $1 + $2, $3, $4 / 1024}' "$tm")"
  rm -f "$tm"
  echo "$log" >&2
  printf '%s\t%s\n' "$label" "$log" >> "$RECORDS"
}
for ((i = 0; i < LEVELS; i++)); do
  cache=()
  [ "$i" -gt 0 ] && cache=(--cache "$WORK/pc_$((i - 1)).h5")
  # shellcheck disable=SC2086
  run "level $i" "$BIN/photoconsist" --scene "$SCENE/scene.h5" --mesh "$WORK/mesh_$i.h5" --level "$i" \
    "${cache[@]}" --out "$WORK/pc_$i.h5" --gt "$SCENE/gt.ply" $EXTRA
  "$BIN/refine" -q --mesh "$WORK/mesh_$i.h5" --active "$WORK/pc_$i.h5" --out "$WORK/mesh_$((i + 1)).h5" >/dev/null 2>&1
done
# shellcheck disable=SC2086
run "scores" "$BIN/photoconsist" --scene "$SCENE/scene.h5" --mesh "$WORK/mesh_$LEVELS.h5" --scores \
  --cache "$WORK/pc_$((LEVELS - 1)).h5" --out "$WORK/scores.h5" --points-ply "$WORK/points.ply" \
  --gt "$SCENE/gt.ply" $EXTRA

python3 - "$RECORDS" "$OUT_JSON" "$OBJECT" <<'EOF'
import json, re, sys
records, out, obj = sys.argv[1], sys.argv[2], sys.argv[3]
runs = []
for line in open(records):
    label, summary = line.rstrip("\n").split("\t", 1)
    m = re.search(r"done in ([0-9.]+) s, peak memory ([0-9.]+) MB", summary)
    rec = {"run": label, "seconds": float(m.group(1)) if m else None,
           "peak_memory_mb": float(m.group(2)) if m else None}
    for k, v in re.findall(r"(\w+)=([-0-9.e]+)", summary):
        try:
            rec[k] = int(v)
        except ValueError:
            rec[k] = float(v)
    runs.append(rec)
json.dump({"benchmark": "photoconsist", "scene": f"synth {obj}, dinoRing cameras (48 x 640x480)",
           "runs": runs}, open(out, "w"), indent=1)
print(f"wrote {out}")
EOF
