#!/usr/bin/env bash
# Installs what is missing, builds everything (warnings as errors) and runs every test; then the
# unit tests and the CLI again under AddressSanitizer and UndefinedBehaviorSanitizer (build-san/,
# any finding fails), then one minute of fuzzing the parser and compiler (build-fuzz/; skipped
# with a message without clang). RT_QUICK=1 stops after the first part.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
jobs=$(nproc)
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DRT_WERROR=ON >/dev/null
cmake --build build -j"$jobs"
ctest --test-dir build --output-on-failure -j"$jobs"
if [ "${RT_QUICK:-0}" = 1 ]; then exit 0; fi

# Sanitizers: only what the unit tests, the crasher corpus and the CLI test need; no GL tests.
echo "test: ASan + UBSan (build-san/)" >&2
cmake -S . -B build-san -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g" \
    -DRT_WERROR=ON -DRT_SANITIZE="address;undefined" -DRT_BUILD_BENCH=OFF -DRT_GL_TESTS=OFF \
    >/dev/null
cmake --build build-san -j"$jobs" --target rt_tests raytrace fuzz_replay
ASAN_OPTIONS=detect_stack_use_after_return=1:strict_string_checks=1 \
    UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    ctest --test-dir build-san --output-on-failure -j"$jobs" -LE gl

# Fuzzing: one minute from the seed corpus (tests/fuzz/run.sh; crashes fail the run).
echo "test: fuzzing for 60 s (build-fuzz/)" >&2
RT_JOBS="$jobs" tests/fuzz/run.sh 60
