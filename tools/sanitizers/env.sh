# Sourced by tools/sanitize-and-fuzz.sh and tools/fuzz-run.sh: how ASan, UBSan and LSan report.
# Every finding is fatal (UBSan too: the build also has -fno-sanitize-recover=undefined), stack
# traces are symbolized, and the suppression files beside this one hold the few findings that are
# a library's fault, each with its reason.
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
symbolizer="$(command -v llvm-symbolizer-15 || command -v /usr/lib/llvm-15/bin/llvm-symbolizer || command -v llvm-symbolizer || true)"
if [ -n "$symbolizer" ]; then
  export ASAN_SYMBOLIZER_PATH="$symbolizer"
  export UBSAN_SYMBOLIZER_PATH="$symbolizer"
fi
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1:suppressions=$here/asan.supp${ASAN_EXTRA_OPTIONS:+:$ASAN_EXTRA_OPTIONS}"
export UBSAN_OPTIONS="halt_on_error=1:abort_on_error=1:print_stacktrace=1:suppressions=$here/ubsan.supp${UBSAN_EXTRA_OPTIONS:+:$UBSAN_EXTRA_OPTIONS}"
export LSAN_OPTIONS="suppressions=$here/lsan.supp:print_suppressions=0${LSAN_EXTRA_OPTIONS:+:$LSAN_EXTRA_OPTIONS}"
