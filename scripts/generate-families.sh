#!/usr/bin/env bash
# Regenerates the shipped AprilTag families with our lexicode generator, resuming any run in
# progress from its checkpoint (detector/codes/families/checkpoints/NAME.ckpt). A 36-bit run can
# take hours: stop it any time (Ctrl-C or kill) and run this again to continue where it stopped.
# Usage: scripts/generate-families.sh [TAGBENCH_BINARY] [FAMILY...]   (default: all shipped)
set -euo pipefail
cd "$(dirname "$0")/.."
BIN=${1:-build/cli/tagbench}
shift || true
FAMILIES=("$@")
[[ ${#FAMILIES[@]} -gt 0 ]] || FAMILIES=(16h5 25h7 25h9 36h15 36h11 36h10 36h9)
DIR=detector/codes/families
mkdir -p "$DIR/checkpoints"
for fam in "${FAMILIES[@]}"; do
  bits=${fam%h*}; ham=${fam#*h}
  out="$DIR/tag$fam.fam"; ckpt="$DIR/checkpoints/tag$fam.ckpt"
  if [[ -f "$out" ]]; then echo "generate-families: $out exists, skipping" >&2; continue; fi
  resume=()
  [[ -f "$ckpt" ]] && resume=(--resume)
  "$BIN" family generate --bits "$bits" --hamming "$ham" --checkpoint "$ckpt" --checkpoint-seconds 30 \
    "${resume[@]}" --out "$out"
done
