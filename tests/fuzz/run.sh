#!/usr/bin/env bash
# Builds the libFuzzer target fuzz_scene (clang, ASan + UBSan, in build-fuzz/) and fuzzes the
# parser and compiler. Usage: tests/fuzz/run.sh [SECONDS|-] [more libFuzzer flags...]
#   tests/fuzz/run.sh 60                  # what scripts/test.sh runs: one minute
#   tests/fuzz/run.sh - -runs=10000000    # a fixed number of executions instead
# Seeds: every .ray/.key file under 64 KB in scenes/, ../shared/public-scenes/ and
# tests/fuzz/corpus/ (copied into a temporary directory, which also receives the new inputs, so
# the repository is never written). A crash leaves its input in build-fuzz/artifacts/: copy it to
# tests/fuzz/crashers/ (the regression corpus every test run replays) and fix the bug.
set -euo pipefail
cd "$(dirname "$0")/../.."
secs=${1:-60}
shift || true
jobs=${RT_JOBS:-$(nproc)}

if ! command -v clang++ >/dev/null ||
    ! compgen -G "/usr/lib/llvm-*/lib/clang/*/lib/linux/libclang_rt.fuzzer-x86_64.a" >/dev/null; then
    echo "fuzz: SKIPPED: needs clang++ and libFuzzer (Debian: clang libclang-rt-14-dev;" \
        "scripts/install-deps.sh installs them)" >&2
    exit 0
fi

cmake -S . -B build-fuzz -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DRT_FUZZ=ON -DRT_SANITIZE="address;undefined" -DRT_BUILD_BENCH=OFF -DRT_GL_TESTS=OFF >/dev/null
cmake --build build-fuzz --target fuzz_scene -j"$jobs"

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/new" "$work/seeds" build-fuzz/artifacts
for d in scenes ../shared/public-scenes tests/fuzz/corpus; do
    [ -d "$d" ] || continue
    find "$d" -type f \( -name '*.ray' -o -name '*.key' \) -size -64k -print0 |
        while IFS= read -r -d '' f; do cp "$f" "$work/seeds/$(printf '%s' "$f" | tr '/' '_')"; done
done

limit=()
if [ "$secs" != "-" ]; then limit=(-max_total_time="$secs"); fi
echo "fuzz: $(ls "$work/seeds" | wc -l) seeds, ${secs}s" >&2
# Absolute paths: the target works in its own temporary directory.
build-fuzz/tests/fuzz/fuzz_scene "$work/new" "$work/seeds" "${limit[@]}" \
    -dict="$PWD/tests/fuzz/ray.dict" -max_len=16384 -timeout=20 -rss_limit_mb=2048 \
    -artifact_prefix="$PWD/build-fuzz/artifacts/" -print_final_stats=1 "$@"
