#!/bin/sh
# The GPU figures the open speed targets need (issues 9, 14 and 15), in one device call.
# On the development machine, in the project root:
#   sh ../shared/gpu/prepare.sh libfmt9 && cp build/decalcomp-bench .gpu/ && cp tools/bench/gpu-round.sh .gpu/
# (libfmt9: the bench links Debian's shared fmt, which the GPU machine lacks.)
# then the device tool with carry [".gpu"] and: sh .gpu/gpu-round.sh
# The tree that travels holds at most 64 MiB and data/ alone is about 60: the bench needs none of
# it, so take data/ out of the index for the call and put it back after (the files stay on disk):
#   git rm -r -q --cached data && echo /data/ >>.git/info/exclude      # before
#   git reset -q && sed -i '\|^/data/$|d' .git/info/exclude            # after
# The first run builds the kernels on NVIDIA: the point-sampled program first (about 40 s on an
# H100), the filter's shading programs (one kernel each, docs/decisions.md) only in the last step,
# in the first case of each filter (the bench says how long that warm-up took). Results land in $OUT (the device
# tool's output folder) as machine.txt, run.log (every step's report) and results.csv (every step's CSV
# rows, each led by the step's name); each step appends as it finishes, so a call that runs out of
# time still brings back the steps before. The tool brings back at most eight files a call.
# The NVIDIA compiler's cache goes to .gpu/nvc and comes back as $OUT/nvc.tgz: unpacked into .gpu/
# on the development machine, the next call carries it and skips the cold builds (the cache grows
# past the 64 MiB carry in a few calls: keep only the newest).
set -u
export CUDA_CACHE_PATH=${CUDA_CACHE_PATH:-$PWD/.gpu/nvc} CUDA_CACHE_MAXSIZE=${CUDA_CACHE_MAXSIZE:-2147483647}
E=${E:-sh .gpu/opencl-env.sh}
B=${B:-./.gpu/decalcomp-bench}
OUT=${OUT:-/tmp/gpu-round}
mkdir -p "$OUT"
{ date -u; nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv; $E clinfo -l; } >"$OUT/machine.txt" 2>&1

# step NAME BENCH-ARGS...: one bench run; its report to run.log, its CSV rows to results.csv.
# KDIR=dir step ...: the kernels from that folder instead of the binary's (an A/B of a kernel change)
# STEP_LIMIT=seconds: stop a step that runs longer (a cold build), so that the steps after it still run
step() {
    name=$1
    shift
    echo "== $name: $(date -u +%H:%M:%S) ${KDIR:+DECALCOMP_KERNEL_DIR=$KDIR }$B $*" >>"$OUT/run.log"
    timeout "${STEP_LIMIT:-0}" env ${KDIR:+DECALCOMP_KERNEL_DIR=$KDIR} $E $B --device nvidia "$@" --csv /tmp/step.csv \
        >>"$OUT/run.log" 2>&1 || echo "== $name: exit status $? (124: past STEP_LIMIT=${STEP_LIMIT:-0} s)" >>"$OUT/run.log"
    [ -f /tmp/step.csv ] && sed "s/^/$name,/" /tmp/step.csv >>"$OUT/results.csv"
    rm -f /tmp/step.csv
}

# the compiler's cache into $OUT, after each build (a call cut short keeps what was built)
save_cache() {
    [ -d "$CUDA_CACHE_PATH" ] && tar czf "$OUT/nvc.tgz" -C "$(dirname "$CUDA_CACHE_PATH")" "$(basename "$CUDA_CACHE_PATH")"
}

# SECTIONS picks what runs and in which order (default: tilekernels issue9 beauty filter); a call
# that may run out of time can take some and leave the rest to the next.
SECTIONS=${SECTIONS:-tilekernels issue9 beauty filter}

# warm-up: builds and caches the point-sampled program
step warmup --quick
save_cache

# Issue 9: composite() against its transfer floors, the kernels against the copy rate, 4096 against 1
section_issue9() {
step issue9 --repeat 10 --sizes 1920x1080,3840x2160 --counts 1,1024,4096 --modes binned
for edge in 3 6; do
    step same-coverage-$edge --repeat 20 --sizes 1920x1080,3840x2160 --counts 1,4096 --modes binned --no-transfers \
        --same-coverage $edge
done
}

# Binning's per-tile kernels on the GPU: the device's rule (--tile-kernels device: grouped coarse
# counts, grouped tile bounds and tests below 96 tiles per compute unit) against each form forced,
# at three tile counts; same binary and program, alternated twice
section_tilekernels() {
for round in 1 2; do
    for kind in device serial groups; do
        step "tiles-$kind-$round" --repeat 20 --sizes 1920x1080,2560x1440,3840x2160 --counts 1,1024,4096 \
            --modes binned --no-transfers --tile-kernels $kind
        step "tiles-$kind-coverage-$round" --repeat 20 --sizes 1920x1080,3840x2160 --counts 1,4096 --modes binned \
            --no-transfers --same-coverage 3 --tile-kernels $kind
    done
done
}

# Issue 14: the beauty update's cost, alternated twice; with KBEFORE=dir also the kernels there
# (steps beauty-kernels-*), with BBEFORE=binary also that bench (steps beauty-binary-before-*: a
# change of the host's layout, which old kernels cannot read)
# beauty_steps NAME: the round's pair, without and with the beauty, named NAME-without-$round and
# NAME-with-$round
beauty_steps() {
    step "$1-without-$round" --repeat 20 --sizes 1920x1080 --counts 1,1024,4096 --modes binned --no-transfers
    step "$1-with-$round" --repeat 20 --sizes 1920x1080 --counts 1,1024,4096 --modes binned --no-transfers --beauty
}
section_beauty() {
for round in 1 2; do
    beauty_steps beauty
    if [ -n "${BBEFORE:-}" ]; then
        B_AFTER=$B
        B=$BBEFORE
        beauty_steps beauty-binary-before
        B=$B_AFTER
    fi
    if [ -n "${KBEFORE:-}" ]; then
        KDIR=$KBEFORE
        beauty_steps beauty-kernels
        KDIR=
    fi
done
}

# Issue 15: Blender's default filter, by taps and in closed form (:fast), against point samples,
# alternated twice (the first run of each builds its shading program)
section_filter() {
for round in 1 2; do
    for filter in none blackman-harris:3 blackman-harris:3:fast; do
        name=${filter%%:*}
        case $filter in *:fast) name=$name-fast ;; esac
        step "filter-$name-$round" --repeat 10 --sizes 1920x1080 --counts 1024 --modes binned --no-transfers \
            --pixel-filter $filter
        [ "$round" = 1 ] && save_cache
    done
done
}

# Filtered frames' clean neighbours: the plane a pass fills first (the GPU's default) against each
# neighbour tested where the silhouette and crease splits scan, alternated twice (not in the default
# SECTIONS; run after filter, which builds the shading programs)
section_cleandepths() {
for round in 1 2; do
    for clean in plane scan; do
        step "clean-$clean-$round" --repeat 10 --sizes 1920x1080 --counts 1024 --modes binned --no-transfers \
            --pixel-filter blackman-harris:3:fast --clean-depths $clean
    done
done
}

# The programs' register caps (docs/decisions.md): the shipped caps against none
# (DECALCOMP_POINT_REGISTERS=0 and DECALCOMP_SHADING_REGISTERS=0), point-sampled with and without
# the beauty and filtered, alternated twice (not in the default SECTIONS; the uncapped programs
# build cold the first time). Each row's last CSV column, output_hash, hashes the composite's
# planes: a shipped row and its uncapped twin should hash alike (the cap changes no arithmetic).
section_caps() {
for round in 1 2; do
    for caps in shipped none; do
        E_CAPS=$E
        [ $caps = none ] && E="env DECALCOMP_POINT_REGISTERS=0 DECALCOMP_SHADING_REGISTERS=0 $E_CAPS"
        step "caps-$caps-point-$round" --repeat 20 --sizes 1920x1080,3840x2160 --counts 1,1024,4096 --modes binned \
            --no-transfers
        step "caps-$caps-beauty-$round" --repeat 20 --sizes 1920x1080 --counts 1024 --modes binned --no-transfers \
            --beauty
        step "caps-$caps-fast-$round" --repeat 10 --sizes 1920x1080 --counts 1024 --modes binned --no-transfers \
            --pixel-filter blackman-harris:3:fast
        E=$E_CAPS
        [ "$round" = 1 ] && save_cache
    done
done
}

# The register caps around the shipped ones (stop 52's next measurement): the point program at 64
# (shipped), 56 and 48 (5 groups of 256 work-items on a multiprocessor instead of 4; 56 a control),
# the shading programs at 128 (shipped) and 96, alternated twice (not in the default SECTIONS).
section_regcaps() {
for round in 1 2; do
    for cap in 64 56 48; do
        E_CAPS=$E
        E="env DECALCOMP_POINT_REGISTERS=$cap $E_CAPS"
        step "regcap-point-$cap-$round" --repeat 10 --sizes 1920x1080,3840x2160 --counts 1,4096 --modes binned \
            --no-transfers
        E=$E_CAPS
    done
    for cap in 128 96; do
        E_CAPS=$E
        E="env DECALCOMP_SHADING_REGISTERS=$cap $E_CAPS"
        step "regcap-shading-$cap-$round" --repeat 10 --sizes 1920x1080 --counts 1024 --modes binned --no-transfers \
            --pixel-filter blackman-harris:3:fast
        E=$E_CAPS
    done
    [ "$round" = 1 ] && save_cache
done
}

# The kernels' CPU flavour on the GPU (DECALCOMP_KERNEL_FLAVOUR=cpu: helpers forced inline, column
# shares in an array, rows read ahead; docs/decisions.md) against the GPU's own, point-sampled and
# `:fast`, alternated twice (not in the default SECTIONS; the CPU flavour builds cold). The hashes
# must agree.
section_flavour() {
for round in 1 2; do
    for flavour in gpu cpu; do
        E_FLAVOUR=$E
        E="env DECALCOMP_KERNEL_FLAVOUR=$flavour $E_FLAVOUR"
        step "flavour-$flavour-point-$round" --repeat 10 --sizes 1920x1080,3840x2160 --counts 1024,4096 \
            --modes binned --no-transfers
        step "flavour-$flavour-fast-$round" --repeat 10 --sizes 1920x1080 --counts 1024 --modes binned \
            --no-transfers --pixel-filter blackman-harris:3:fast
        E=$E_FLAVOUR
        [ "$round" = 1 ] && save_cache
    done
done
}

# A/B of kernel changes: the binary's kernels against each folder of AB_KERNELS (space-separated,
# e.g. ".gpu/k1 .gpu/k2", copies of kernels/ with a change each), alternated AB_ROUNDS times (default
# 2), with the bench arguments AB_ARGS (default: issue 15's `:fast` case). Rows are ab-NAME-ROUND,
# NAME "base" or the folder's name; compare their output_hash to see whether a change kept the bytes.
section_ab() {
for round in $(seq "${AB_ROUNDS:-2}"); do
    for kdir in base ${AB_KERNELS:-}; do
        # shellcheck disable=SC2086
        if [ "$kdir" = base ]; then
            step "ab-base-$round" ${AB_ARGS:---repeat 10 --sizes 1920x1080 --counts 1024 --modes binned --no-transfers --pixel-filter blackman-harris:3:fast}
        else
            KDIR=$kdir
            step "ab-$(basename "$kdir")-$round" ${AB_ARGS:---repeat 10 --sizes 1920x1080 --counts 1024 --modes binned --no-transfers --pixel-filter blackman-harris:3:fast}
            KDIR=
        fi
    done
    [ "$round" = 1 ] && save_cache
done
}

# Issue 9's batch bar: `decalcomp batch` against `--io-only` on the same 32 frames of 1080p with
# 1,000 decals, and `--io-only` on the batch's own outputs (the floor of any batch that writes
# them), alternated three times, then one `--timing` run (not in the default SECTIONS;
# BATCH_FRAMES and BATCH_DEVICE change the 32 frames and the device, e.g. for a try on PoCL). Needs the
# batch's runtime in .gpu-batch (tools/bench-batch/gpu-runtime.sh .gpu-batch, then
# cp /usr/bin/time .gpu-batch/: the host has none), carried with .gpu. Its lines go to batch.log.
section_batch() {
LL=$(sh .gpu-batch/unpack.sh /tmp/rt | tail -1)
RT=/tmp/rt/bin
IN='/tmp/bb/in/f.####.exr'
W='/tmp/bb/w/f.####.exr'
N=${BATCH_FRAMES:-32}
SCENE="--decals /tmp/bb/scene/scene.json --device ${BATCH_DEVICE:-nvidia}"
batch() { LD_LIBRARY_PATH=$LL $E $RT/decalcomp batch "$@" >>"$OUT/batch.log" 2>&1; }
# shellcheck disable=SC2086 # $E: a command and its arguments
timed() { label=$1; shift; rm -rf /tmp/bb/w; LD_LIBRARY_PATH=$LL .gpu-batch/time -f "$label %e s %M KB %P %U u" \
    $E $RT/decalcomp batch "$@" >>"$OUT/batch.log" 2>&1; }
LD_LIBRARY_PATH=$LL MAKE_ONLY=1 BIN=$RT OIIOTOOL=$RT/oiiotool sh tools/bench-batch/run.sh /tmp/bb "$N" nvidia 1 1920x1080 1000 \
    >>"$OUT/batch.log" 2>&1
# shellcheck disable=SC2086
batch "$IN" -o '/tmp/bb/warm/f.####.exr' --frames 1-2 -q $SCENE
for round in 1 2 3; do
    # shellcheck disable=SC2086
    timed "batch-$round" "$IN" -o "$W" --frames "1-$N" -q $SCENE
    rm -rf /tmp/bb/out && mv /tmp/bb/w /tmp/bb/out
    timed "io-only-$round" "$IN" -o "$W" --frames "1-$N" -q --io-only
    timed "io-only-composited-$round" '/tmp/bb/out/f.####.exr' -o "$W" --frames "1-$N" -q --io-only
done
rm -rf /tmp/bb/w
# shellcheck disable=SC2086
batch "$IN" -o "$W" --frames "1-$N" --timing $SCENE
ls -l /tmp/bb/in/f.0001.exr /tmp/bb/out/f.0001.exr >>"$OUT/batch.log" 2>&1
}

for section in $SECTIONS; do section_$section; done
date -u >>"$OUT/machine.txt"
save_cache
