#!/usr/bin/env bash
# Installs what is missing, builds everything (warnings as errors) and the web page (build-web/)
# and runs every test, the page's in headless Chromium among them, and the core tests again with
# the baseline kernels (RAYTRACER_ISA=sse2); then the
# unit tests, the fuzz crasher corpus, the CLI test and the viewer's chaos test (500 random
# scripted events) again under AddressSanitizer and UndefinedBehaviorSanitizer (build-san/, any
# finding fails, no GL tests), then 30 s of fuzzing each fuzz target (the parser and compiler,
# the image decoders, key files, part files, raycompare's comparison; tests/fuzz/run.sh) in that
# same tree, then the viewer's tests (the trace restarted 1000 times with edits) and the load's threads under
# ThreadSanitizer (build-tsan/).
# With clang and libFuzzer the sanitizer tree is clang's (it also builds the fuzz targets);
# without them it is GCC's and fuzzing is skipped with a message. RT_QUICK=1 stops after the
# first part.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
jobs=$(nproc)
. scripts/build-env.sh
# Each part's time, to keep the whole under 30 minutes on 2 cores.
start=$SECONDS
last=$SECONDS
took() {
    echo "test: $1 took $((SECONDS - last)) s ($((SECONDS - start)) s in all)" >&2
    last=$SECONDS
}
# Every tree is a unity build (a few files compiled as one): build/ in 290 s instead of 452 s,
# the same tests passing and the same BVH speed against Embree (raybench).
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DRT_WERROR=ON -DCMAKE_UNITY_BUILD=ON >/dev/null
cmake --build build -j"$jobs"
took "building build/"
# The web page, for its test in headless Chromium (tests/web): built once, into build-web/.
if command -v emcmake >/dev/null; then
    RT_WEB_JOBS="$jobs" ./scripts/build-web.sh
else
    echo "test: Emscripten is not installed: the web page is not built (its test skips)" >&2
fi
took "building the web page"
ctest --test-dir build --output-on-failure -j"$jobs"
took "the tests in build/"
# The core tests once more with the baseline kernels (the tests above ran the widest ones this
# CPU has; tests/app/test_isa.sh compares the images of each).
RAYTRACER_ISA=sse2 build/tests/rt_tests --gtest_brief=1
took "the core tests under RAYTRACER_ISA=sse2"
if [ "${RT_QUICK:-0}" = 1 ]; then exit 0; fi

echo "test: ASan + UBSan (build-san/)" >&2
export ASAN_OPTIONS=detect_stack_use_after_return=1:strict_string_checks=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
if tests/fuzz/run.sh check 2>/dev/null; then
    RT_FUZZ_BUILD=build-san RT_JOBS="$jobs" \
        RT_FUZZ_TARGETS="rt_tests rt_load_thread_tests rt_app_tests rt_viewer_tests raytrace
            raymerge imgdiff rayview raycompare" \
        tests/fuzz/run.sh build
    fuzz=1
else
    cmake -S . -B build-san -DCMAKE_BUILD_TYPE=RelWithDebInfo \
        -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" -DRT_WERROR=ON \
        -DRT_SANITIZE="address;undefined;float-cast-overflow" -DRT_BUILD_BENCH=OFF \
        -DRT_GL_TESTS=OFF -DCMAKE_UNITY_BUILD=ON >/dev/null
    cmake --build build-san -j"$jobs" --target rt_tests rt_load_thread_tests rt_app_tests \
        rt_viewer_tests raytrace raymerge imgdiff rayview raycompare fuzz_replay
    fuzz=0
fi
took "building build-san/"
# The estimate's statistics test renders 256-spp references of four scenes: 9 s here, 160 s
# under the sanitizers, for code the other progressive tests run too.
# The instruction sets' test renders scenes/ only there (every public scene too in build/).
# The independent renderer's class (diagnose_minirender: 160 Python renders, then raycompare
# --diagnose with some 1,800 mutant renders) scores the diagnosis, which build/ runs; under the
# sanitizers the diagnosis runs in test_diagnose, the fits' tests and test_raycompare.sh.
RT_ISA_SHIPPED_ONLY=1 ctest --test-dir build-san --output-on-failure -j"$jobs" \
    -LE "gl|install|web" \
    -E "^(Progressive.TheEstimateIsWithinAQuarterOfTheTrueError|diagnose_minirender)$"
took "the tests in build-san/"

# Fuzzing: 30 s of each target from its seeds (crashes fail the run). libFuzzer keeps one core
# busy: the ThreadSanitizer tree builds beside it, and its log is shown when it ends.
fuzz_pid=""
if [ "$fuzz" = 1 ]; then
    echo "test: fuzzing 5 targets for 30 s each (build-san/, log in build-san/fuzz.log)" \
        "beside build-tsan/" >&2
    # A process group of its own (setsid), so that a failure below stops libFuzzer with it.
    RT_FUZZ_BUILD=build-san RT_JOBS="$jobs" setsid tests/fuzz/run.sh 30 >build-san/fuzz.log 2>&1 &
    fuzz_pid=$!
    trap '[ -z "$fuzz_pid" ] || kill -- "-$fuzz_pid" 2>/dev/null || true' EXIT
else
    tests/fuzz/run.sh check || true  # prints why it is skipped
fi

# ThreadSanitizer: the viewer's state and its trace threads (no GL; Mesa is not loaded), and the
# load on several threads (the parse of mesh runs, the compile's loops). The sanitizer trees are unity builds (CMAKE_UNITY_BUILD:
# a few files compiled as one), which build in about half the time (TSan 149 -> 84 s, ASan ~490
# -> 373 s on 2 cores).
echo "test: ThreadSanitizer (build-tsan/)" >&2
# The SSE2 kernels alone (RT_WIDE_KERNELS=OFF): these tests do not reach the kernels, and the
# AVX2 and AVX-512 ones take 96 s of the core's 274 s of compile time (build/, GCC -O3).
cmake -S . -B build-tsan -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" -DRT_WERROR=ON -DRT_SANITIZE=thread \
    -DRT_BUILD_BENCH=OFF -DRT_GL_TESTS=OFF -DRT_WIDE_KERNELS=OFF -DCMAKE_UNITY_BUILD=ON >/dev/null
cmake --build build-tsan -j"$jobs" --target rt_viewer_tests rt_load_thread_tests
took "building build-tsan/"
if [ -n "$fuzz_pid" ]; then
    status=0
    wait "$fuzz_pid" || status=$?
    fuzz_pid=""
    grep -E "^(fuzz:|Done|stat::number_of_executed_units|==[0-9]+==|SUMMARY)" build-san/fuzz.log \
        >&2 || true
    if [ "$status" != 0 ]; then
        tail -n 60 build-san/fuzz.log >&2
        echo "test: fuzzing failed (exit $status; the input is in build-san/artifacts/)" >&2
        exit 1
    fi
    took "waiting for the fuzzing"
fi
TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1" \
    ctest --test-dir build-tsan --output-on-failure -j"$jobs" -R "^(Viewer|Tracer|MeshRuns|CompileThreads)\."
took "the tests in build-tsan/"
