# Sanitizer run-time options for the sanitizer suite (build-asan/) and the
# fuzzers (build-fuzz/); sourced by scripts/test.sh and scripts/fuzz.sh.
# Locally: source scripts/sanitizers/env.sh && ctest --test-dir build-asan
# No suppressions: every report so far was fixed in clothfit's code
# (docs/reliability.md). halt_on_error: the first report fails the test;
# detect_leaks: LeakSanitizer (part of ASan on Linux) checks at exit.
export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
