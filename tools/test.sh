#!/bin/sh
# Installs the dependencies (Debian 12), builds decalcomp and runs the whole test suite, then the
# second build: the suite again under ASan+UBSan and every fuzz target for 30 s
# (tools/sanitize-and-fuzz.sh, docs/fuzzing.md; DECALCOMP_SANITIZE_STAGE=0 leaves it out).
set -eu
cd "$(dirname "$0")/.."
sh tools/install-deps.sh
# No debug info in CI's build: the same optimised code, a third less compile and link time.
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -DNDEBUG" \
  -DDECALCOMP_WERROR=ON
cmake --build build -j"$(nproc)"
sanitize=${DECALCOMP_SANITIZE_STAGE:-1}
if [ "$sanitize" != 0 ]; then
  # The sanitizer build runs beside this stage's tests at the lowest priority: it takes the cores
  # that the tests leave idle while they wait on the processes they start (docs/fuzzing.md).
  nice -n 19 bash tools/sanitize-and-fuzz.sh --build-only >build/sanitize-build.log 2>&1 &
  sanitize_build=$!
fi
# One more test than cores: many tests wait on the processes they start (the CLI, PoCL's start).
(cd build && ctest --output-on-failure -j"$(($(nproc) + 1))" "$@") || tests_failed=1
if [ "$sanitize" != 0 ]; then
  wait "$sanitize_build" || sanitize_build_failed=1
  echo "==== the sanitizer build (build/sanitize-build.log)"
  cat build/sanitize-build.log
  [ -z "${sanitize_build_failed:-}" ] || { echo "the sanitizer build failed" >&2; exit 1; }
fi
[ -z "${tests_failed:-}" ] || exit 1
if [ "$sanitize" != 0 ]; then
  bash tools/sanitize-and-fuzz.sh --no-build 30
fi
