#!/usr/bin/env bash
# The parser and compiler under libFuzzer: builds the target fuzz_scene with clang, ASan and UBSan
# (in $RT_FUZZ_BUILD, build-fuzz/ by default) and fuzzes it.
#   tests/fuzz/run.sh 60                  # one minute (scripts/test.sh does this in build-san/)
#   tests/fuzz/run.sh - -runs=10000000    # a fixed number of executions instead
#   tests/fuzz/run.sh check               # exit 0 when clang and libFuzzer are installed
#   tests/fuzz/run.sh build               # configure and build only ($RT_FUZZ_TARGETS too)
# Seeds: every .ray/.key file under 64 KB in scenes/, ../shared/public-scenes/ and
# tests/fuzz/corpus/ (copied into a temporary directory, which also receives the new inputs, so
# the repository is never written). A crash leaves its input in $RT_FUZZ_BUILD/artifacts/: copy it
# to tests/fuzz/crashers/ (the regression corpus every test run replays) and fix the bug.
set -euo pipefail
cd "$(dirname "$0")/../.."
secs=${1:-60}
shift || true
jobs=${RT_JOBS:-$(nproc)}
dir=${RT_FUZZ_BUILD:-build-fuzz}

if ! command -v clang++ >/dev/null ||
    ! compgen -G "/usr/lib/llvm-*/lib/clang/*/lib/linux/libclang_rt.fuzzer-x86_64.a" >/dev/null; then
    echo "fuzz: SKIPPED: needs clang++ and libFuzzer (Debian: clang libclang-rt-14-dev;" \
        "scripts/install-deps.sh installs them)" >&2
    [ "$secs" = check ] && exit 1
    exit 0
fi
[ "$secs" = check ] && exit 0

# -O1 -g1: the tree is also the sanitizer tree of scripts/test.sh, built from scratch there.
cmake -S . -B "$dir" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" -DRT_FUZZ=ON \
    -DRT_SANITIZE="address;undefined;float-cast-overflow" \
    -DRT_BUILD_BENCH=OFF -DRT_GL_TESTS=OFF >/dev/null
# shellcheck disable=SC2086
cmake --build "$dir" --target fuzz_scene ${RT_FUZZ_TARGETS:-} -j"$jobs"
[ "$secs" = build ] && exit 0

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/new" "$work/seeds" "$dir/artifacts"
for d in scenes ../shared/public-scenes tests/fuzz/corpus; do
    [ -d "$d" ] || continue
    find "$d" -type f \( -name '*.ray' -o -name '*.key' \) -size -64k -print0 |
        while IFS= read -r -d '' f; do cp "$f" "$work/seeds/$(printf '%s' "$f" | tr '/' '_')"; done
done

limit=()
if [ "$secs" != "-" ]; then limit=(-max_total_time="$secs"); fi
echo "fuzz: $(ls "$work/seeds" | wc -l) seeds, ${secs}s" >&2
# Absolute paths: the target works in its own temporary directory.
"$dir/tests/fuzz/fuzz_scene" "$work/new" "$work/seeds" "${limit[@]}" \
    -dict="$PWD/tests/fuzz/ray.dict" -max_len=16384 -timeout=20 -rss_limit_mb=2048 \
    -artifact_prefix="$PWD/$dir/artifacts/" -print_final_stats=1 "$@"
