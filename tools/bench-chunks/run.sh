#!/bin/sh
# Chunk-rewrite benchmark (issue 13, docs/benchmarks.md "Chunk rewrite"): a 1920x1080 Blender frame
# with 48 FLOAT channels in ZIP (the generator's 15 channels plus 33 renamed copies, as AOVs), a
# scene of DECALS box decals centred on rows FIRST-LAST (so they cover about a fifth of the rows),
# and, in one run, alternating: `oiiotool IN -o OUT` (read and write the same file), `decalcomp
# composite` of the BEFORE and AFTER builds, and `decalcomp batch` of both over FRAMES copies.
# Wall time from /usr/bin/time -v; medians over REPEATS.
#
#   BEFORE=dir AFTER=dir sh tools/bench-chunks/run.sh [WORK] [REPEATS] [FRAMES] [DECALS] [FIRST] [LAST]
#
# BEFORE and AFTER hold decalcomp (AFTER also decalcomp-gbuffer-gen and decalcomp-bench-batch).
set -eu
WORK=${1:-/tmp/decalcomp-bench-chunks}
REPEATS=${2:-3}
FRAMES=${3:-8}
DECALS=${4:-7}
FIRST=${5:-480}
LAST=${6:-600}
: "${BEFORE:?BEFORE=folder of the old decalcomp}" "${AFTER:?AFTER=folder of the new decalcomp}"
mkdir -p "$WORK/seq"
cd "$WORK"
if [ ! -f frame48.exr ]; then
  "$AFTER/decalcomp-gbuffer-gen" --width 1920 --height 1080 --compression zip --header-camera -o base.exr > /dev/null
  CH=$(oiiotool --info -v base.exr | sed -n 's/^ *channel list: //p' | tr -d ' ' | tr ',' ' ')
  names() { for c in $CH; do printf "%s," "ViewLayer.AOV$1_${c#ViewLayer.}"; done | sed 's/,$//'; }
  oiiotool base.exr --chnames "$(names A)" -o a.exr
  oiiotool base.exr --chnames "$(names B)" -o b.exr
  oiiotool base.exr --ch 0,1,2 --chnames "$(names C | cut -d, -f1-3)" -o c.exr
  oiiotool base.exr a.exr --chappend b.exr --chappend c.exr --chappend --compression zip -o frame48.exr
  rm -f a.exr b.exr c.exr
fi
"$AFTER/decalcomp-bench-batch" --decals "$DECALS" --min-size 0.1 --max-size 0.3 --first-row "$FIRST" \
  --last-row "$LAST" -o scene > /dev/null
f=1
while [ "$f" -le "$FRAMES" ]; do cp frame48.exr "seq/f.$(printf %04d "$f").exr"; f=$((f + 1)); done
cat frame48.exr seq/*.exr > /dev/null  # page cache
"$AFTER/decalcomp" composite frame48.exr --decals scene/scene.json --device cpu --stats -o stats.exr | grep -E '^(stats: chunks|chunks)'

wall() { awk -F': ' '/Elapsed \(wall clock\)/ {n = split($2, t, ":"); s = 0; for (i = 1; i <= n; i++) s = s * 60 + t[i]; print s}' "$1"; }
run() {  # NAME COMMAND...: appends "NAME seconds" to times
  name=$1; shift
  rm -rf out; mkdir -p out
  /usr/bin/time -v -o time.txt "$@" > log.txt 2>&1 || { cat log.txt >&2; exit 1; }
  echo "$name $(wall time.txt)" >> times
}
rm -f times
i=1
while [ "$i" -le "$REPEATS" ]; do
  run oiiotool oiiotool frame48.exr -o out/o.exr
  run composite-before "$BEFORE/decalcomp" composite frame48.exr --decals scene/scene.json --device cpu -q -o out/c.exr
  run composite-after "$AFTER/decalcomp" composite frame48.exr --decals scene/scene.json --device cpu -q -o out/c.exr
  run batch-before "$BEFORE/decalcomp" batch 'seq/f.####.exr' --decals scene/scene.json --device cpu -q -o 'out/f.####.exr'
  run batch-after "$AFTER/decalcomp" batch 'seq/f.####.exr' --decals scene/scene.json --device cpu -q -o 'out/f.####.exr'
  i=$((i + 1))
done
median() { grep "^$1 " times | awk '{print $2}' | sort -n | awk '{a[NR] = $1} END {print a[int((NR + 1) / 2)]}'; }
O=$(median oiiotool)
for n in oiiotool composite-before composite-after batch-before batch-after; do
  m=$(median "$n")
  printf '%-17s median %6.2f s  (%s)  %.2fx oiiotool' "$n" "$m" "$(grep "^$n " times | awk '{printf "%s ", $2}')" \
    "$(echo "$m $O" | awk '{print $1 / $2}')"
  case $n in batch-*) printf '  %.2f fps' "$(echo "$FRAMES $m" | awk '{print $1 / $2}')" ;; esac
  echo
done
