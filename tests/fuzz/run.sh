#!/usr/bin/env bash
# The fuzz targets under libFuzzer (tests/fuzz/CMakeLists.txt: scene, image, key, part,
# compare): builds them with clang, ASan and UBSan (in $RT_FUZZ_BUILD, build-fuzz/ by default)
# and fuzzes each in turn for SECS seconds.
#   tests/fuzz/run.sh 30                  # 30 s each (scripts/test.sh does this in build-san/)
#   tests/fuzz/run.sh 300 image           # only the targets named
#   tests/fuzz/run.sh - -runs=10000000    # a fixed number of executions instead (every target)
#   tests/fuzz/run.sh check               # exit 0 when clang and libFuzzer are installed
#   tests/fuzz/run.sh build               # configure and build only ($RT_FUZZ_TARGETS too)
# Seeds: tests/fuzz/corpus/TARGET, plus for the scene target every .ray/.key file under 64 KB in
# scenes/ and ../shared/public-scenes/, for the key target their .key files, for the image target
# scenes/textures, for the compare target the image target's seeds (copied into a temporary
# directory, which also receives the new inputs, so the repository is never written). Arguments
# after the targets go to libFuzzer. A crash leaves its input in
# $RT_FUZZ_BUILD/artifacts/TARGET-...: copy it to tests/fuzz/crashers/TARGET/ (the regression
# corpus every test run replays) and fix the bug.
set -euo pipefail
cd "$(dirname "$0")/../.."
. scripts/build-env.sh
secs=${1:-30}
shift || true
all=(scene image key part compare)
targets=()
while [ $# -gt 0 ] && [[ " ${all[*]} " == *" $1 "* ]]; do
    targets+=("$1")
    shift
done
[ ${#targets[@]} -gt 0 ] || targets=("${all[@]}")
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

# -O1 -g1: the tree is also the sanitizer tree of scripts/test.sh, built from scratch there; a
# unity build (a few files compiled as one), which builds in about three quarters of the time.
cmake -S . -B "$dir" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" -DRT_FUZZ=ON \
    -DRT_SANITIZE="address;undefined;float-cast-overflow" \
    -DRT_BUILD_BENCH=OFF -DRT_GL_TESTS=OFF -DCMAKE_UNITY_BUILD=ON >/dev/null
# shellcheck disable=SC2086
cmake --build "$dir" --target "${all[@]/#/fuzz_}" ${RT_FUZZ_TARGETS:-} -j"$jobs"
[ "$secs" = build ] && exit 0

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$dir/artifacts"

# seeds TARGET: copies the target's seeds into $work/TARGET/seeds.
seeds() {
    local out="$work/$1/seeds" d pattern=()
    mkdir -p "$out" "$work/$1/new"
    local dirs=("tests/fuzz/corpus/$1")
    case $1 in
        scene) dirs+=(scenes ../shared/public-scenes) pattern=(-name '*.ray' -o -name '*.key') ;;
        key) dirs+=(scenes ../shared/public-scenes) pattern=(-name '*.key') ;;
        image) dirs+=(scenes/textures) pattern=(-name '*.*') ;;
        part) pattern=(-name '*.part') ;;
        compare) dirs+=(tests/fuzz/corpus/image) pattern=(-name '*.*') ;;
    esac
    for d in "${dirs[@]}"; do
        [ -d "$d" ] || continue
        find "$d" -type f \( "${pattern[@]}" \) ! -name '*.md' ! -name '*.py' -size -64k -print0 |
            while IFS= read -r -d '' f; do cp "$f" "$out/$(printf '%s' "$f" | tr '/' '_')"; done
    done
}

# Each target's dictionary and largest input: the .ray/.key vocabulary for the scene and key
# targets, file magic and chunk names for the images (and the compared images), the header
# words for the parts.
options() {
    case $1 in
        scene) echo "-dict=$PWD/tests/fuzz/ray.dict -max_len=16384" ;;
        key) echo "-dict=$PWD/tests/fuzz/ray.dict -max_len=8192" ;;
        image) echo "-dict=$PWD/tests/fuzz/image.dict -max_len=8192" ;;
        part) echo "-dict=$PWD/tests/fuzz/part.dict -max_len=4096" ;;
        compare) echo "-dict=$PWD/tests/fuzz/image.dict -max_len=8192" ;;
    esac
}

limit=()
if [ "$secs" != "-" ]; then limit=(-max_total_time="$secs"); fi
status=0
for t in "${targets[@]}"; do
    seeds "$t"
    echo "fuzz: $t: $(find "$work/$t/seeds" -type f | wc -l) seeds, ${secs}s" >&2
    # Absolute paths: the targets work in their own temporary directories.
    # shellcheck disable=SC2046
    "$dir/tests/fuzz/fuzz_$t" "$work/$t/new" "$work/$t/seeds" "${limit[@]}" $(options "$t") \
        -timeout=20 -rss_limit_mb=2048 -artifact_prefix="$PWD/$dir/artifacts/$t-" \
        -print_final_stats=1 "$@" || status=$?
    [ "$status" = 0 ] || break
done
exit "$status"
