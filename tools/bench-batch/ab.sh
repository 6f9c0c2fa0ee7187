#!/bin/sh
# Two builds of decalcomp on the batch bench's frames (made by run.sh): `batch` with the scene and
# `batch --io-only`, the builds alternated ROUNDS times in one run, wall time, peak RSS and CPU from
# /usr/bin/time. For a change to the batch's own pipeline, whose figures move with the machine.
#
#   BEFORE=dir AFTER=dir sh tools/bench-batch/ab.sh [WORK_DIR] [FRAMES] [DEVICE] [ROUNDS] [WIDTHxHEIGHT] [DECALS]
#
# BEFORE and AFTER hold a decalcomp binary each; AFTER also decalcomp-gbuffer-gen and
# decalcomp-bench-batch, which make the frames. BATCH_ARGS adds options to every run, TIME_BIN
# overrides /usr/bin/time. Prints "round N before|after io-only|batch WALL_S PEAK_KB CPU".
set -eu
WORK=${1:-/tmp/decalcomp-bench-batch}
FRAMES=${2:-32}
DEVICE=${3:-gpu}
ROUNDS=${4:-3}
SIZE=${5:-1920x1080}
DECALS=${6:-1000}
TIME_BIN=${TIME_BIN:-/usr/bin/time}
HERE=$(cd "$(dirname "$0")" && pwd)
: "${BEFORE:?BEFORE=dir with the decalcomp to compare against}" "${AFTER:?AFTER=dir with the changed decalcomp}"

MAKE_ONLY=1 BIN=$AFTER sh "$HERE/run.sh" "$WORK" "$FRAMES" "$DEVICE" 1 "$SIZE" "$DECALS"
IN="$WORK/in/f.####.exr"
# run BIN KIND: one timed batch into $WORK/ab-out
run() {
  rm -rf "$WORK/ab-out"
  if [ "$2" = io-only ]; then set -- "$1" --io-only; else set -- "$1" --decals "$WORK/scene/scene.json" --device "$DEVICE"; fi
  bin=$1
  shift
  # shellcheck disable=SC2086
  "$TIME_BIN" -f "%e %M %P" -o "$WORK/ab-time" "$bin/decalcomp" batch "$IN" -o "$WORK/ab-out/f.####.exr" \
    --frames "1-$FRAMES" "$@" -q ${BATCH_ARGS:-} 2> "$WORK/ab-log" || { cat "$WORK/ab-log" >&2; exit 1; }
}
for bin in "$BEFORE" "$AFTER"; do  # warm-up: kernel builds, the binaries in the page cache
  "$bin/decalcomp" batch "$IN" -o "$WORK/ab-out/f.####.exr" --frames 1-2 --decals "$WORK/scene/scene.json" \
    --device "$DEVICE" -q 2> "$WORK/ab-log" || { cat "$WORK/ab-log" >&2; exit 1; }
done
round=1
while [ "$round" -le "$ROUNDS" ]; do
  for side in before after; do
    bin=$BEFORE
    [ "$side" = after ] && bin=$AFTER
    for kind in io-only batch; do
      run "$bin" "$kind"
      echo "round $round $side $kind $(cat "$WORK/ab-time")"
    done
  done
  round=$((round + 1))
done
rm -rf "$WORK/ab-out"
