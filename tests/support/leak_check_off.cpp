// Linked into the few test binaries, in the sanitizer build only, where LeakSanitizer's exit-time
// scan crashes in its own tracer thread ("Tracer caught signal 11", then "LeakSanitizer has
// encountered a fatal error"): test_kernel_sources and test_occlusion, with PoCL's CPU-device
// threads still alive at exit. The crash is clang 15's LSan reading those threads' dynamic TLS
// (LSAN_OPTIONS=use_tls=0 avoids it, but then reports the thread-local data of OpenImageIO's
// dependencies as leaks). ASan and UBSan stay on in these binaries; every other binary, the CLI
// included, is leak-checked. docs/fuzzing.md lists it with the suppressions.
extern "C" int __lsan_is_turned_off() { return 1; }
