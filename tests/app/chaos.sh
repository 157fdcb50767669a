#!/usr/bin/env bash
# The viewer under random scripted input: camera moves, light edits, picks, settings (extreme
# and non-finite values included), undo and redo, opens of good, broken and missing files,
# saves, background renders. It must never crash, leak or raise a GL error; a command that is
# refused (bad value, nothing to undo) is fine. Under ASan + UBSan in scripts/test.sh.
# usage: chaos.sh RAYVIEW SOURCE_DIR [EVENTS [SEED]]
set -u
rv=$(realpath "$1")
src=$(realpath "$2")
events=${3:-500}
RANDOM=${4:-14}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
export XDG_CONFIG_HOME="$tmp/config"
# Mesa's software GL driver leaks a few bytes at exit: suppressed by its library names only.
printf 'leak:libGLX_mesa.so\nleak:swrast_dri.so\nleak:libgallium\nleak:libLLVM\nleak:libglapi.so\n' \
    >"$tmp/lsan.supp"
export LSAN_OPTIONS="suppressions=$tmp/lsan.supp:print_suppressions=0"
export ASAN_OPTIONS="${ASAN_OPTIONS:-}:exitcode=99"

echo '#shape_sphere 0  0 0 0  1' >"$tmp/broken.ray"
scenes=("$src"/scenes/*.ray "$tmp/broken.ray" "$tmp/missing.ray")
numbers=(0 0.1 -0.3 1 2.5 -7 100 1e6 -1e6 1e-9 nan inf -inf x)
# Each helper leaves its pick in a variable (no subshell), so a seed replays the same script.
num() { N="${numbers[RANDOM % ${#numbers[@]}]}"; }
small() { S="0.$((RANDOM % 100))"; }
pick() {
    local a=("$@")
    P="${a[RANDOM % ${#a[@]}]}"
}
event() {
    num
    small
    case $((RANDOM % 34)) in
    0 | 1 | 2) echo "orbit $S -0.$((RANDOM % 100))" ;;
    3) echo "look $N $S" ;;
    4) echo "pan $S $N" ;;
    5) echo "dolly $N" ;;
    6) echo "fly $N $S $S" ;;
    7) echo "light $((RANDOM % 4)) colour $S $N 1" ;;
    8) echo "light $((RANDOM % 4)) position $N $S $S" ;;
    9) echo "light $((RANDOM % 4)) radius $N" ;;
    10) pick point spot directional sphere cone && echo "add-light $P" ;;
    11) echo "frame-light $((RANDOM % 5))" ;;
    12 | 13) echo "pick 0.$((RANDOM % 1000)) 0.$((RANDOM % 1000))" ;;
    14) pick on off maybe && echo "shadows $P" ;;
    15) echo "depth $((RANDOM % 12 - 1))" ;;
    16) echo "resolution $N" ;;
    17) echo "boxes $((RANDOM % 4)) $((RANDOM % 4))" ;;
    18) pick both preview trace && echo "layout $P" ;;
    19) echo "exposure $N" ;;
    20) pick clamp reinhard aces none && echo "tonemap $P" ;;
    21) pick on off && echo "headlight $P" ;;
    22 | 23) pick undo redo && echo "$P" ;;
    24) pick "${scenes[@]}" && echo "open $P" ;;
    25) pick "${scenes[@]}" && echo "open-background $P" ;;
    26) pick reload "markers off" "markers on" "help on" "help off" "threads 1" && echo "$P" ;;
    27) pick ray png pfm && local ext=$P && pick save-scene save-image && echo "$P $tmp/out.$ext" ;;
    28 | 29) pick play pause "loop on" "loop off" && echo "$P" ;;
    30) pick time speed fps && echo "$P $N" ;;
    31) pick nearest linear catmull-rom bspline cubic && echo "interpolation $P" ;;
    32) pick matrix closest euler log quaternion spin && echo "rotation $P" ;;
    33) pick "$tmp/anim_%d.png" "$tmp/anim.png" && echo "render-animation $P 2 16 12 1" ;;
    esac
}
for ((i = 0; i < events; ++i)); do
    printf '%d ' $((i + 5))
    event
done >"$tmp/chaos.txt"
echo "$((events + 6)) render-image $tmp/final.png 32 24 2" >>"$tmp/chaos.txt"
[ -n "${CHAOS_KEEP:-}" ] && cp "$tmp/chaos.txt" "$CHAOS_KEEP.script"

"$(dirname "$0")/xrun.sh" "$rv" --size 960x540 --script "$tmp/chaos.txt" \
    "$src/scenes/showpiece.ray" >"$tmp/out.txt" 2>&1
rc=$?
[ -n "${CHAOS_KEEP:-}" ] && cp "$tmp/out.txt" "$CHAOS_KEEP"
refused=$(grep -c "error:" "$tmp/out.txt")
echo "chaos: $events events (seed ${4:-14}), exit $rc, $refused commands refused with a message"
if grep -q -E "AddressSanitizer|LeakSanitizer|runtime error|GL error|Segmentation|Aborted" \
    "$tmp/out.txt" || { [ "$rc" != 0 ] && [ "$rc" != 1 ]; }; then
    grep -E -B2 -A30 "AddressSanitizer|LeakSanitizer|runtime error|GL error" "$tmp/out.txt" | head -80
    echo "--- the run's last lines:"
    tail -40 "$tmp/out.txt"
    echo "FAIL: the viewer crashed, leaked or raised a GL error (exit $rc)"
    exit 1
fi
echo "chaos: passed"
