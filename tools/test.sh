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
# One more test than cores: many tests wait on the processes they start (the CLI, PoCL's start).
(cd build && ctest --output-on-failure -j"$(($(nproc) + 1))" "$@")
if [ "${DECALCOMP_SANITIZE_STAGE:-1}" != 0 ]; then
  bash tools/sanitize-and-fuzz.sh 30
fi
