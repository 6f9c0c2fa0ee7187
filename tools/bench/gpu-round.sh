#!/bin/sh
# The GPU figures the open speed targets need (issues 9, 14 and 15), in one device call.
# On the development machine, in the project root:
#   sh ../shared/gpu/prepare.sh && cp build/decalcomp-bench .gpu/ && cp tools/bench/gpu-round.sh .gpu/
# then the device tool with carry [".gpu"] and: sh .gpu/gpu-round.sh
# The first run builds the kernels (minutes on NVIDIA; the driver caches them for the runs after).
# Everything lands in $OUT (the device tool's output folder), one log per step (plain file names:
# the device tool does not bring back names with odd characters).
set -u
E="sh .gpu/opencl-env.sh"
B=./.gpu/decalcomp-bench
OUT=${OUT:-/tmp/gpu-round}
mkdir -p "$OUT"
{ date -u; nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv; $E clinfo -l; } >"$OUT/machine.txt" 2>&1

# warm-up: builds and caches the program of point-sampled frames (the filter's full program is
# built by the last step, which may run out of a call's time on a cold machine)
$E $B --device nvidia --quick >"$OUT/warmup.log" 2>&1

# Issue 9: composite() against its transfer floors, the kernels against the copy rate, 4096 against 1
$E $B --device nvidia --repeat 10 --sizes 1920x1080,3840x2160 --counts 1,1024,4096 --modes binned \
    --csv "$OUT/issue9.csv" >"$OUT/issue9.log" 2>&1
for edge in 3 6; do
    $E $B --device nvidia --repeat 20 --sizes 1920x1080,3840x2160 --counts 1,4096 --modes binned --no-transfers \
        --same-coverage $edge --csv "$OUT/same-coverage-$edge.csv" >"$OUT/same-coverage-$edge.log" 2>&1
done

# Issue 14: the beauty update's cost, alternated twice
for round in 1 2; do
    for beauty in without with; do
        flag=""
        [ "$beauty" = with ] && flag=--beauty
        $E $B --device nvidia --repeat 20 --sizes 1920x1080 --counts 1,1024,4096 --modes binned --no-transfers \
            $flag --csv "$OUT/beauty-$beauty-$round.csv" >"$OUT/beauty-$beauty-$round.log" 2>&1
    done
done

# Issue 15: Blender's default filter against point samples, alternated twice
for round in 1 2; do
    for filter in none blackman-harris:3; do
        $E $B --device nvidia --repeat 10 --sizes 1920x1080 --counts 1024 --modes binned --no-transfers \
            --pixel-filter $filter --csv "$OUT/filter-${filter%%:*}-$round.csv" >"$OUT/filter-${filter%%:*}-$round.log" 2>&1
    done
done
date -u >>"$OUT/machine.txt"
