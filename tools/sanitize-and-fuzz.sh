#!/bin/bash
# CI's second build (docs/fuzzing.md): the whole project with clang-15 under AddressSanitizer and
# UndefinedBehaviorSanitizer, with libFuzzer's coverage instrumentation, so one build serves both:
#  1. the test suite under ASan+UBSan; any sanitizer report from any process fails, also one from
#     a CLI run whose exit code a test does not look at (reports go to files, checked at the end);
#  2. every fuzz target for SECONDS (default 30) on seeds from data/.
#   tools/sanitize-and-fuzz.sh [SECONDS]      build dir: $DECALCOMP_SANITIZE_BUILD or build-fuzz
# CTest's selection arguments go in CTEST_ARGS (e.g. "-R Masks"). By default the pixel filter's
# accuracy tests against supersampled truth (brute-force double-precision compositing of 6x frames,
# minutes under ASan), its binned/unbinned twin and all but the first seed of its kernel-vs-reference
# test are left out: the same host code runs under ASan in KernelMatchesReference/1 (docs/fuzzing.md).
# So are the two 10,000-decal ordering tests (three minutes each of the scalar reference under ASan;
# the tile lists' host code runs in CompositorFrames.OverflowingTileListsRunAgainAndMatchUnbinned).
# And the accuracy checks against Blender renders and supersampled truth added with bake mode
# (TextureSpaceBakeBlender, TextureSpace.FilteredDecalMatchesSupersampledTruth, bake seeds 1-3):
# their host code (CLI composite and batch, the bake, the rest pass, the reference) runs under ASan
# in the CLI, bake and kernel-vs-reference tests kept here. The executables that only check
# accuracy (Blender truth, our own renders, determinism, the generator) are not even built here
# (DECALCOMP_TESTS_NOT_SANITIZED in tests/CMakeLists.txt).
# The random kernel, occlusion and material scenes run their first three seeds here (the gcc
# stage runs every seed; the host code is the same for each), and BatchKill's SIGKILLs are left to
# the gcc stage: a killed process reports nothing, and resuming runs under ASan in BatchSignals.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
seconds=${1:-30}
build=${DECALCOMP_SANITIZE_BUILD:-build-fuzz}
jobs=${JOBS:-$(nproc)}

# -O1 keeps the sanitizers' stack traces exact and the build short; line tables are all the
# symbolizer needs. No NDEBUG: assertions stay on.
cmake -S . -B "$build" -G Ninja -DCMAKE_CXX_COMPILER=clang++-15 -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only" -DDECALCOMP_SANITIZE=ON -DDECALCOMP_FUZZ=ON
cmake --build "$build" -j"$jobs"

# 1. The whole suite, the slurm test included.
reports="$(cd "$build" && pwd)/sanitizer-reports"  # absolute: tests and the CLI run in other folders
rm -rf "$reports" && mkdir -p "$reports"
(
  export ASAN_EXTRA_OPTIONS="log_path=$reports/asan:log_exe_name=1"
  export UBSAN_EXTRA_OPTIONS="log_path=$reports/ubsan:log_exe_name=1"
  # Each test process is leak-checked once, at its exit, after its own threads' thread-locals are
  # gone. Leaving the other threads' dynamic TLS out of that scan (use_tls=0) keeps LeakSanitizer's
  # tracer from crashing on PoCL's device threads, in whichever binary's memory layout triggers it
  # (docs/fuzzing.md). The fuzzers keep the default: libFuzzer checks leaks while the process
  # lives, when thread-local strings are still in use.
  export LSAN_EXTRA_OPTIONS="use_tls=0"
  # shellcheck source=tools/sanitizers/env.sh
  . tools/sanitizers/env.sh
  cd "$build"
  # One process per test executable, not per test (tools/sanitizers/run_grouped.py): under the
  # sanitizers each process costs about half a second to start and to leak-check, and the stage
  # ran 716 s one test a process against 331 s grouped. One more process than cores: the CLI tests
  # spend much of their time starting processes (ASan's shadow memory, PoCL). The signal tests,
  # which time a signal against a running batch, keep a process each: grouped, they missed it.
  # shellcheck disable=SC2086
  python3 "$root/tools/sanitizers/run_grouped.py" . "$((jobs + 1))" --separate 'Signals[.]' ${CTEST_ARGS:--E PixelFilterTruth|FilteredRandomScenes.BinnedEqualsUnbinned|FilteredRandomScenes.KernelMatchesReference/[2-9]|Ordering.TenThousand|TextureSpaceBakeBlender|FilteredDecalMatchesSupersampledTruth|BakeKernelMatchesReference.*/[1-9]|(Kernels/RandomScenes|Occlusion/OcclusionScenes|Materials/MaterialScenes)[.].*/([4-9]|[1-9][0-9])\$|BatchKill}
) || suite_failed=1
failed=""
if [ -n "$(ls -A "$reports")" ]; then
  for f in "$reports"/*; do echo "==== sanitizer report $f"; cat "$f"; done
  failed="sanitizer reports above"
fi
[ -z "${suite_failed:-}" ] || failed="${failed:+$failed; }test suite failed under ASan/UBSan"

# 2. Fuzzing, on seeds from data/; run even after a failed suite, so one CI run tells both.
tools/fuzz-seeds.sh "$build" "$build/fuzz-seeds"
tools/fuzz-run.sh "$build" "$seconds" || failed="${failed:+$failed; }a fuzz target failed"
if [ -n "$failed" ]; then
  echo "sanitize-and-fuzz: $failed" >&2
  exit 1
fi
