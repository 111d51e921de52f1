#!/usr/bin/env bash
# `make bench`: regenerates everything in results/ and the README's tables from it.
# Usage: scripts/run-bench.sh [BUILD_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build}
BIN=$BUILD/cli/tagbench
PY=/usr/bin/python3   # Debian's python3, which has python3-matplotlib
mkdir -p results

echo "bench: code experiments (code table, Fig. 5, false-positive theory)" >&2
"$BIN" codes --out results
"$PY" scripts/plot_codes.py results

echo "bench: lexicode generator speed" >&2
"$BIN" generator-speed --out results/generator_speed.csv

echo "bench: decoding speed (Google Benchmark)" >&2
tmp=$(mktemp --suffix=.json)
trap 'rm -f "$tmp"' EXIT
"$BUILD/bench/bench_codes" --benchmark_out="$tmp" --benchmark_out_format=json --benchmark_min_time=0.3 >&2
TAGBENCH_CPU="$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//')" \
  "$PY" scripts/bench_to_csv.py "$tmp" results/decode_speed.csv
cp "$tmp" results/decode_speed.json.tmp && mv results/decode_speed.json.tmp results/decode_speed.json

echo "bench: example detection and the stage pictures of the paper's Figs. 3 and 4" >&2
mkdir -p results/debug
"$BIN" scene --width 640 --height 480 --count 6 --seed 3 -o results/example_scene.png
"$BIN" detect results/example_scene.png --profile paper --draw results/example_detections.png --debug-dir results/debug \
  --camera 500,500,319.5,239.5 --tag-size 0.1 > results/example_detections.json
# The default profile's own stage pictures (threshold classes, boundary groups, quads) of the same scene.
mkdir -p results/debug/default
"$BIN" detect results/example_scene.png --debug-dir results/debug/default > /dev/null

echo "bench: our per-stage times on synthetic scenes beside libapriltag and OpenCV aruco (Google Benchmark)" >&2
"$BUILD/bench/bench_detector" --benchmark_out="$tmp" --benchmark_out_format=json --benchmark_min_time=0.5 >&2
TAGBENCH_CPU="$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//')" \
  "$PY" scripts/speed_to_csv.py "$tmp" results/speed_stages.csv
cp "$tmp" results/speed_stages.json.tmp && mv results/speed_stages.json.tmp results/speed_stages.json

echo "bench: ray-traced localization (paper Figs. 9 and 10, and conditions and the 6-DoF sweep beyond the paper)" >&2
# Frames are cached in $BUILD/raytrace-cache: a rerun renders nothing, an interrupted run resumes.
RT_CACHE=$BUILD/raytrace-cache
"$BIN" raytrace angle --trials 50 --cache "$RT_CACHE" --out results
"$BIN" raytrace distance --trials 50 --cache "$RT_CACHE" --out results
# The distance sweep for the small families too (issue 17, section 5: range at least libapriltag d1's for
# 16h5 and 25h9 as for 36h11): another family's files carry its name, results/fig10_distance_16h5*.csv and
# results/fig10_distance_25h9*.csv, beside the 36h11 figure's. From 3 m: their white border is wider for
# the same 1 m black square (a printed tag of 8/6 and 9/7 of it, 36h11's 10/8), so at 2 m a tag turned
# 45 degrees in the image would not be whole in view and the sweep refuses the step.
FAMILY_DISTANCES=3,4,5,6,7,8,9,10,12.5,15,17.5,20,22.5,25,27.5,30,32.5,35,37.5,40,42.5,45,47.5,50,52.5,55,57.5,60
for fam in 16h5 25h9; do
  "$BIN" raytrace distance --family "$fam" --distances "$FAMILY_DISTANCES" --trials 50 --cache "$RT_CACHE" --out results
done
"$BIN" raytrace conditions --trials 50 --cache "$RT_CACHE" --out results
# The FMAC protocol's 6-DoF sweep (issue 12, section 4): 1000 Halton frames of distance, phi, tilt axis,
# roll and image position through a camera with a lens, defocus, noise and 8 bits; every built-in detector.
"$BIN" raytrace sixdof --frames 1000 --cache "$RT_CACHE" --out results
# The same frames as datasets any detector can be run on and scored against (README "Benchmark your own
# detector"): PNG files and truth.json in $BUILD/datasets/{angle,distance,conditions,sixdof}, from the cache.
for exp in angle distance conditions; do
  "$BIN" dataset export "$exp" --trials 50 --cache "$RT_CACHE" --out "$BUILD/datasets/$exp"
done
"$BIN" dataset export sixdof --frames 1000 --cache "$RT_CACHE" --out "$BUILD/datasets/sixdof"
# Figs. 9 and 10 also draw the paper's Java AprilTag 1 and ARToolKitPlus, run outside the build on these
# frames: read from ../shared/reference/external_runs/ when it is there, else from results/external/.
"$PY" scripts/plot_raytrace.py results angle distance conditions
"$PY" scripts/plot_sixdof.py results

echo "bench: the realistic image set (small tags, JPEG photographs' camera; issue 17)" >&2
"$BIN" realistic --frames 200 --ceiling --out results
"$PY" scripts/plot_realistic.py results
# The same set with another seed, which no choice of the default profile was measured on (every
# issue-17 decision used seed 1): how far the seed-1 numbers carry to frames nobody tuned for.
"$BIN" realistic --frames 200 --seed 2 --ceiling --detectors tagbench,tagbench-thorough,tagbench-half,libapriltag-d1,libapriltag-d2 \
  --out results/realistic_seed2
# The same set (seed 1) printed in 16h5 and 25h9, the other families of the distance sweeps: whether what
# was measured in 36h11 carries to codes that correct fewer bits (16h5's line quads gave no tag until
# session 31, which only such a run shows).
for fam in 16h5 25h9; do
  "$BIN" realistic --frames 200 --family "$fam" \
    --detectors tagbench,tagbench-thorough,tagbench-half,libapriltag-d1,libapriltag-d2 --out "results/realistic_$fam"
done
# The same frames (seed 1) from a linear camera (a machine-vision camera with its gamma off): darker
# shadows and faint prints, 8-bit steps where tags are dark; our detectors are told gamma 1.
"$BIN" realistic --frames 200 --camera-gamma 1 \
  --detectors tagbench,tagbench-thorough,tagbench-half,libapriltag-d1,libapriltag-d2 --out results/realistic_linear
# Where our detectors lost the tags they missed (issue 17, section 2): per distance step and size bin.
"$PY" scripts/loss_breakdown.py results/fig10_distance_summary.csv --out results/fig10_distance_loss.csv
"$PY" scripts/loss_breakdown.py results/realistic_summary.csv --out results/realistic_loss.csv
"$PY" scripts/loss_breakdown.py results/realistic_seed2/realistic_summary.csv --out results/realistic_seed2/realistic_loss.csv

echo "bench: detection peak memory at 640x480, 1920x1080 and 8000x8000" >&2
# A fresh child process per measurement; making the 8000x8000 scene takes about 3 GB for a moment.
"$BUILD/bench/detect_memory" --out results/memory.csv --sizes 640x480,1920x1080,8000x8000

echo "bench: natural-image corpus from Debian packages (built once, then found) and its candidate quads" >&2
# TAGBENCH_CORPUS: where the corpus lives (default corpus/, git-ignored; about 1 GB with the .deb cache).
CORPUS=${TAGBENCH_CORPUS:-corpus}
JOBS=$(nproc)
manifest_before=$(stat -c %Y "$CORPUS/manifest.tsv" 2>/dev/null || echo none)
t0=$(date +%s%N)
"$BIN" corpus build --out "$CORPUS" --jobs "$JOBS"
t1=$(date +%s%N)
manifest_after=$(stat -c %Y "$CORPUS/manifest.tsv" 2>/dev/null || echo none)
build_did_work=0
[[ "$manifest_before" != "$manifest_after" ]] && build_did_work=1
"$BIN" corpus candidates --corpus "$CORPUS" --jobs "$JOBS"
t2=$(date +%s%N)
"$PY" scripts/corpus_stats.py results "$CORPUS" $(((t1 - t0) / 1000000)) "$build_did_work" \
  $(((t2 - t1) / 1000000)) "$JOBS"

echo "bench: false positives on the corpus (paper Figs. 6 and 7, whole detectors, decision margin)" >&2
"$BIN" falsepos complexity --candidates "$CORPUS/corpus_candidates.bin" --out results
"$BIN" falsepos codes --candidates "$CORPUS/corpus_candidates.bin" --out results
"$BIN" falsepos detectors --corpus "$CORPUS" --out results --jobs "$JOBS"
# Beyond the paper: a minimum decision margin, scored on the corpus (false side) and on ray-traced
# 16h5 and 25h9 frames (true side: distance sweep, noise and blur), frames cached with the others.
"$BIN" falsepos margin --corpus "$CORPUS" --out results --trials 50 --cache "$RT_CACHE" --jobs "$JOBS"
"$PY" scripts/plot_falsepos.py results

echo "bench: detector speed on four image sets (corpus, ray-traced frames, realistic set, synthetic scenes)" >&2
# Every detector single-threaded in one process, alternating image by image; ratios per image. At most
# 1200 images a set: every corpus image, 1200 of the cached ray-traced frames (evenly spread).
"$BIN" speed --corpus "$CORPUS" --cache "$RT_CACHE" --max-images 1200 --out results

"$PY" scripts/update_readme.py README.md results
echo "bench: results/ and README.md updated" >&2
