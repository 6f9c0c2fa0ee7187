#!/bin/sh
# Batch benchmark (docs/benchmarks.md "Batch"): `decalcomp batch` over a sequence of generator
# frames (ZIP; depth, albedo, normal, object id, position and an untouched beauty layer) with N
# decals, against `oiiotool` reading and writing the same frames with the same compression (the
# cost of the I/O alone), and against `decalcomp batch --io-only`. Wall time and peak memory from
# /usr/bin/time -v; medians over the repeats.
#
#   BIN=build-batch sh tools/bench-batch/run.sh [WORK_DIR] [FRAMES] [DEVICE] [REPEATS] [WIDTHxHEIGHT] [DECALS]
#
# BIN holds decalcomp, decalcomp-gbuffer-gen and decalcomp-bench-batch; OIIOTOOL and TIME_BIN
# override the tools; BATCH_ARGS adds options to the compositing runs (e.g. "--workers 2"); MAKE_ONLY=1
# makes the frames and scenes and stops.
set -eu
WORK=${1:-/tmp/decalcomp-bench-batch}
FRAMES=${2:-48}
DEVICE=${3:-gpu}
REPEATS=${4:-3}
SIZE=${5:-1920x1080}
DECALS=${6:-1000}
BIN=${BIN:-build}
OIIOTOOL=${OIIOTOOL:-oiiotool}
TIME_BIN=${TIME_BIN:-/usr/bin/time}
W=${SIZE%x*}
H=${SIZE#*x}

mkdir -p "$WORK/in"
if [ ! -f "$WORK/in/f.$(printf %04d "$FRAMES").exr" ] || [ ! -f "$WORK/scene/scene.json" ]; then
  echo "making $FRAMES frames of ${W}x$H and a scene of $DECALS decals in $WORK" >&2
  "$BIN/decalcomp-gbuffer-gen" --width "$W" --height "$H" --compression zip --header-camera -o "$WORK/in/f.0001.exr"
  f=2
  while [ "$f" -le "$FRAMES" ]; do cp "$WORK/in/f.0001.exr" "$WORK/in/f.$(printf %04d "$f").exr"; f=$((f + 1)); done
  "$BIN/decalcomp-bench-batch" --width "$W" --height "$H" --decals "$DECALS" -o "$WORK/scene"
  "$BIN/decalcomp-bench-batch" --width "$W" --height "$H" --decals "$DECALS" --animate "$FRAMES" -o "$WORK/scene-animated"
fi
cat "$WORK"/in/*.exr > /dev/null  # page cache: every run reads from memory
[ -z "${MAKE_ONLY:-}" ] || exit 0  # MAKE_ONLY=1: the frames and scenes, no runs (ab.sh)
echo "frame: $(ls -l "$WORK/in/f.0001.exr" | awk '{print $5}') bytes; channels:" >&2
"$BIN/decalcomp" info "$WORK/in/f.0001.exr" 2>&1 | sed -n '2,30p' | grep -E '^\s+\S+ \((float|half|uint)\)' | tr -s ' ' | tr '\n' ' ' >&2
echo >&2

# run NAME COMMAND...: one timed run into $WORK/out-NAME; appends "NAME wall_s maxrss_kb" to $WORK/times
run() {
  name=$1
  shift
  rm -rf "$WORK/out-$name"
  mkdir -p "$WORK/out-$name"
  sync
  "$TIME_BIN" -v -o "$WORK/time.txt" "$@" > "$WORK/log-$name.txt" 2>&1 || { cat "$WORK/log-$name.txt" >&2; exit 1; }
  wall=$(awk -F': ' '/Elapsed \(wall clock\)/ {n = split($2, t, ":"); s = 0; for (i = 1; i <= n; i++) s = s * 60 + t[i]; print s}' "$WORK/time.txt")
  rss=$(awk -F': ' '/Maximum resident set size/ {print $2}' "$WORK/time.txt")
  cpu=$(awk -F': ' '/Percent of CPU/ {print $2}' "$WORK/time.txt")
  echo "$name $wall $rss $cpu" >> "$WORK/times"
  printf '  %-16s %8.2f s  %7.2f fps  peak %6.0f MB  CPU %s\n' "$name" "$wall" "$(echo "$FRAMES $wall" | awk '{print $1 / $2}')" "$(echo "$rss" | awk '{print $1 / 1024}')" "$cpu" >&2
}

IN="$WORK/in/f.####.exr"
# Warm-up: kernel build caches, the driver, the binaries.
"$BIN/decalcomp" batch "$IN" -o "$WORK/warm/f.####.exr" --frames 1-2 --decals "$WORK/scene/scene.json" --device "$DEVICE" -q
rm -rf "$WORK/warm" "$WORK/times"
i=1
while [ "$i" -le "$REPEATS" ]; do
  echo "repeat $i" >&2
  run oiiotool "$OIIOTOOL" --frames "1-$FRAMES" "$WORK/in/f.#.exr" -o "$WORK/out-oiiotool/f.#.exr"
  run io-only "$BIN/decalcomp" batch "$IN" -o "$WORK/out-io-only/f.####.exr" --frames "1-$FRAMES" --io-only -q
  # shellcheck disable=SC2086
  run batch "$BIN/decalcomp" batch "$IN" -o "$WORK/out-batch/f.####.exr" --frames "1-$FRAMES" \
    --decals "$WORK/scene/scene.json" --device "$DEVICE" -q ${BATCH_ARGS:-}
  # shellcheck disable=SC2086
  run animated "$BIN/decalcomp" batch "$IN" -o "$WORK/out-animated/f.####.exr" --frames "1-$FRAMES" \
    --decals "$WORK/scene-animated/scene.json" --device "$DEVICE" -q ${BATCH_ARGS:-}
  i=$((i + 1))
done

median() { grep "^$1 " "$WORK/times" | awk '{print $'"$2"'}' | sort -n | awk '{v[NR] = $1} END {print v[int((NR + 1) / 2)]}'; }
echo "output bytes: oiiotool $(cat "$WORK"/out-oiiotool/*.exr | wc -c), batch $(cat "$WORK"/out-batch/*.exr | wc -c)"
io=$(median oiiotool 2)
echo "median over $REPEATS repeats, $FRAMES frames of ${W}x$H, $DECALS decals, device '$DEVICE':"
for name in oiiotool io-only batch animated; do
  wall=$(median "$name" 2)
  rss=$(median "$name" 3)
  cpu=$(median "$name" 4)
  echo "$name $wall $rss $io $FRAMES $cpu" | awk '{printf "  %-10s %8.2f s  %7.2f fps  %5.3fx oiiotool  peak RSS %6.0f MB  CPU %s\n", $1, $2, $5 / $2, $2 / $4, $3 / 1024, $6}'
done
# The I/O alone for frames like the outputs (composited albedo compresses worse than the input's).
run io-composited "$BIN/decalcomp" batch "$WORK/out-batch/f.####.exr" -o "$WORK/out-io-composited/f.####.exr" \
  --frames "1-$FRAMES" --io-only -q
run oiiotool-composited "$OIIOTOOL" --frames "1-$FRAMES" "$WORK/out-batch/f.#.exr" -o "$WORK/out-oiiotool-composited/f.#.exr"
