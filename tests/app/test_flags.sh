#!/usr/bin/env bash
# Every flag that a program's --help documents is accepted by it: each program runs once per
# flag, with a value and the companions the flag needs, and must exit 0. A flag added to a
# --help without an entry here fails the test until it gets one. Also: --config FILE gives the
# image its options give, an unknown flag is a usage error (exit 2), and --version names the
# program.
# usage: test_flags.sh BUILD_APP_DIR SOURCE_DIR
set -u
bin=$(realpath "$1")
src=$(realpath "$2")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
source "$(dirname "$0")/check.sh"
cd "$tmp" || exit 1
scene="$src/scenes/simple.ray"
export XDG_CONFIG_HOME="$tmp/config"

# The long names of the flags a --help lists ("  -o,--output FILE=..." gives --output).
flags_of() {
    "$1" --help | grep -oE '^  (-[a-zA-Z],)?--[a-z][-a-z0-9]*' | sed 's/.*,//; s/^ *//' | sort -u
}

# check_flags PROGRAM BASE_ARGS TABLE: runs PROGRAM BASE_ARGS ARGS for each flag, ARGS from the
# associative array named TABLE ("alone" entries run without BASE_ARGS).
check_flags() {
    local prog=$1 base=$2 table=$3 flag name
    local -n args=$table
    name=$(basename "$prog")
    if [ ! -x "$prog" ]; then  # a tree that builds only some programs (the sanitizer tree)
        echo "test_flags: $name is not built here: its flags are not tested"
        return
    fi
    for flag in $(flags_of "$prog"); do
        if [ -z "${args[$flag]+set}" ]; then
            check "$name $flag has an entry in test_flags.sh" false
            continue
        fi
        local a=${args[$flag]} cmd
        if [[ $a == alone:* ]]; then cmd="$prog ${a#alone:}"; else cmd="$prog $base $a"; fi
        if ! eval "$cmd" >"$tmp/out.txt" 2>&1; then
            echo "  $cmd:"
            sed 's/^/    /' "$tmp/out.txt" | head -n 5
            check "$name accepts $flag" false
        else
            check "$name accepts $flag" true
        fi
    done
}

echo "spp = 2" >"$tmp/cfg.toml"

# raytrace: a 24x16 render of a small scene per flag.
declare -A rt=(
    [--help]="alone:--help" [--version]="alone:--version" [--config]="--config $tmp/cfg.toml"
    [--output]="-o $tmp/x.pfm" [--width]="--width 20" [--height]="--height 10"
    [--depth]="--depth 2" [--cutoff]="--cutoff 0.01" [--spp]="--spp 2"
    [--light-samples]="--light-samples 4" [--seed]="--seed 3" [--threads]="--threads 1"
    [--no-shadows]="--no-shadows" [--dialect]="--dialect v1"
    [--missing-textures]="--missing-textures checker" [--stats]="--stats"
    [--explain]="--explain" [--no-specialize]="--no-specialize" [--quiet]="--quiet"
    [--progressive]="--progressive --spp 2" [--time]="--progressive --time 0.05"
    [--target-error]="--progressive --target-error 0.5"
    [--reference]="--progressive --spp 2 --reference auto --reference-spp 2"
    [--reference-spp]="--progressive --spp 2 --reference auto --reference-spp 4"
    [--report]="--progressive --spp 2 --report $tmp/r.csv"
    [--plot]="--progressive --spp 2 --plot $tmp/p.svg"
    [--adaptive]="--progressive --spp 4 --adaptive"
    [--light-radius]="--light-radius 0.1" [--aperture]="--aperture 0.05"
    [--focus-distance]="--focus-distance 3" [--roughness]="--roughness 0.1"
    [--at]="--at 0.5" [--interpolation]="--at 0.5 --interpolation linear"
    [--rotation]="--at 0.5 --rotation euler" [--frames]="--frames 2 -o $tmp/f_%02d.png"
    [--fps]="--frames 2 --fps 12 -o $tmp/f_%02d.png"
    [--start]="--frames 2 --start 1 -o $tmp/f_%02d.png"
    [--video]="--frames 2 -o $tmp/v_%02d.png --video $tmp/v.mp4" [--frame]="--frame 1"
    [--tile]="--tile 0,0,12,8 -o $tmp/t.part" [--samples]="--spp 2 --samples 0:1 -o $tmp/s.part"
    [--exr-float]="-o $tmp/e.exr --exr-float" [--aov]="-o $tmp/e.exr --aov albedo,depth"
    [--max-pixels]="--max-pixels 1000"
    [--inspect]="alone:$scene --width 24 --height 16 --inspect 3,4"
    [--inspect-sample]="alone:$scene --width 24 --height 16 --spp 2 --inspect 3,4 --inspect-sample 1"
    [--inspect-json]="alone:$scene --width 24 --height 16 --inspect 3,4 --inspect-json $tmp/i.json"
    [--inspect-depth]="alone:$scene --width 24 --height 16 --inspect 3,4 --inspect-depth 1"
    [--inspect-light]="alone:$scene --width 24 --height 16 --inspect 3,4 --inspect-light 0"
    [--mistake]="--mistake no-shadows"
)
check_flags "$bin/raytrace" "$scene --width 24 --height 16 -q -o $tmp/o.png" rt

# rayview without a display renders headless (to simple.png here): every flag parses the same.
: >"$tmp/empty_script.txt"
{ printf 'P6\n24 16\n255\n'; head -c $((24 * 16 * 3)) /dev/zero; } >"$tmp/black.ppm"
declare -A rv=(
    [--help]="alone:--help" [--version]="alone:--version" [--config]="--config $tmp/cfg.toml"
    [--frames]="--frames 1" [--screenshot]="--frames 1 --screenshot $tmp/shot.png"
    [--script]="--script $tmp/empty_script.txt" [--layout]="--layout preview"
    [--size]="--size 800x600" [--panel]="--panel off" [--width]="--width 20"
    [--height]="--height 10" [--depth]="--depth 2" [--cutoff]="--cutoff 0.01" [--spp]="--spp 2"
    [--light-samples]="--light-samples 4" [--seed]="--seed 3" [--threads]="--threads 1"
    [--no-shadows]="--no-shadows" [--no-specialize]="--no-specialize" [--dialect]="--dialect v1"
    [--target-error]="--target-error 0.01" [--missing-textures]="--missing-textures checker"
    [--light-radius]="--light-radius 0.1" [--aperture]="--aperture 0.05"
    [--focus-distance]="--focus-distance 3" [--roughness]="--roughness 0.1"
    [--max-pixels]="--max-pixels 1000" [--compare]="--compare $tmp/black.ppm"
)
DISPLAY= WAYLAND_DISPLAY= check_flags "$bin/rayview" "$scene --width 24 --height 16 --spp 1" rv
if [ -x "$bin/rayview" ]; then  # headless, --compare prints the comparison's figures
    DISPLAY= WAYLAND_DISPLAY= "$bin/rayview" "$scene" --compare "$tmp/black.ppm" >"$tmp/rv_cmp.txt"
    check "rayview --compare headless prints the figures" \
        grep -qE "^rayview: vs black.ppm: mean \|diff\| [0-9.]+ .* off by > 8/255" "$tmp/rv_cmp.txt"
    DISPLAY= WAYLAND_DISPLAY= "$bin/rayview" "$scene" --compare "$tmp/none.png" 2>"$tmp/rv_cmp.txt"
    check "rayview --compare of a missing file exits 1" test $? -eq 1
    check "and says why" grep -q "cannot compare with $tmp/none.png" "$tmp/rv_cmp.txt"
fi

declare -A gen=(
    [--help]="alone:--help" [--version]="alone:--version" [--config]="--config $tmp/gen.toml"
    [--triangles]="--triangles 200" [--output]="-o $tmp/g2.ray"
)
echo "triangles = 100" >"$tmp/gen.toml"
check_flags "$bin/raygen" "-n 50 -o $tmp/g.ray" gen

"$bin/raytrace" "$scene" --width 24 --height 16 --tile 0,0,24,8 -q -o "$tmp/a.part"
"$bin/raytrace" "$scene" --width 24 --height 16 --tile 0,8,24,16 -q -o "$tmp/b.part"
echo "quiet = true" >"$tmp/merge.toml"
declare -A merge=(
    [--help]="alone:--help" [--version]="alone:--version" [--config]="--config $tmp/merge.toml"
    [--output]="-o $tmp/m2.png" [--quiet]="--quiet" [--max-pixels]="--max-pixels 1000"
)
check_flags "$bin/raymerge" "-o $tmp/m.png $tmp/a.part $tmp/b.part" merge

echo "max-mad = 255" >"$tmp/diff.toml"
"$bin/raytrace" "$scene" --width 24 --height 16 -q -o "$tmp/d1.png"
"$bin/raytrace" "$scene" --width 24 --height 16 --spp 2 -q -o "$tmp/d2.png"
declare -A diff=(
    [--help]="alone:--help" [--version]="alone:--version" [--config]="--config $tmp/diff.toml"
    [--max-mad]="--max-mad 255" [--max-dark-share]="--max-dark-share 1" [--crop]="--crop 0 0 4 4"
    [--max-abs]="--max-abs 1" [--off]="--off 16" [--max-off-share]="--max-off-share 1"
)
check_flags "$bin/imgdiff" "$tmp/d1.png $tmp/d2.png" diff

# raycompare: d1.png against the scene's reference (--max-bad 1: every setting passes).
echo "tolerance = 16" >"$tmp/cmp.toml"
declare -A cmp=(
    [--help]="alone:--help" [--version]="alone:--version" [--config]="--config $tmp/cmp.toml"
    [--tolerance]="--tolerance 16" [--max-bad]="--max-bad 0.5" [--neighbourhood]="--neighbourhood"
    [--csv]="--csv $tmp/c.csv" [--html]="--html $tmp/report" [--quiet]="--quiet"
    [--depth]="--depth 2" [--cutoff]="--cutoff 0.01" [--spp]="--spp 2"
    [--light-samples]="--light-samples 4" [--seed]="--seed 3" [--threads]="--threads 1"
    [--no-shadows]="--no-shadows" [--no-specialize]="--no-specialize" [--dialect]="--dialect v1"
    [--missing-textures]="--missing-textures checker" [--max-pixels]="--max-pixels 1000"
    [--light-radius]="--light-radius 0.1" [--aperture]="--aperture 0.05"
    [--focus-distance]="--focus-distance 3" [--roughness]="--roughness 0.1"
    [--lossy]="--lossy" [--size]="--size any" [--heat-scale]="--heat-scale 32" [--gradescope]="--gradescope $tmp/g.json"
    [--diagnose]="--diagnose"
)
check_flags "$bin/raycompare" "$scene $tmp/d1.png --max-bad 1" cmp

# What each program requires, so the flag tested is the one error.
declare -A needs=([raytrace]="$scene" [rayview]="$scene" [raygen]="-o $tmp/g3.ray"
    [raymerge]="-o $tmp/m3.png $tmp/a.part $tmp/b.part" [imgdiff]="$tmp/d1.png $tmp/d2.png"
    [raycompare]="$scene $tmp/d1.png")

# --config: the options of a file are those of the command line.
printf 'width = 32\nheight = 20\nspp = 4\nno-shadows = true\nlight-radius = 0.2\n' >"$tmp/render.toml"
"$bin/raytrace" "$scene" --config "$tmp/render.toml" -q -o "$tmp/c1.pfm"
"$bin/raytrace" "$scene" --width 32 --height 20 --spp 4 --no-shadows --light-radius 0.2 -q -o "$tmp/c2.pfm"
check "raytrace --config gives the image of the same options" cmp -s "$tmp/c1.pfm" "$tmp/c2.pfm"
check "and the size it names" grep -qa "^32 20$" "$tmp/c1.pfm"
"$bin/raytrace" "$scene" --config "$tmp/render.toml" --width 16 -q -o "$tmp/c3.pfm"
check "a flag given too wins over the file" grep -qa "^16 20$" "$tmp/c3.pfm"
echo "no-such-option = 3" >"$tmp/bad.toml"
"$bin/raytrace" "$scene" --config "$tmp/bad.toml" -q -o "$tmp/c4.png" 2>"$tmp/err.txt"
check "an unknown key in the file is a usage error" test $? -eq 2
check "which names it" grep -q "no-such-option" "$tmp/err.txt"
"$bin/raytrace" "$scene" --config "$tmp/missing.toml" -q -o "$tmp/c5.png" 2>"$tmp/err.txt"
check "a missing config file is a usage error" test $? -eq 2
check "no image after a usage error" test ! -e "$tmp/c4.png" -a ! -e "$tmp/c5.png"
# Only a regular file is read as a config: a FIFO would block forever (timeout: a hang fails
# the check, it is no measurement) and /dev/zero never ends.
mkfifo "$tmp/fifo.toml"
for config in "$tmp/fifo.toml" /dev/zero "$tmp"; do
    for prog in raytrace rayview raygen raymerge imgdiff raycompare; do
        [ -x "$bin/$prog" ] || continue
        eval "DISPLAY= timeout 60 '$bin/$prog' ${needs[$prog]} --config $config" \
            >/dev/null 2>"$tmp/err.txt"
        check "$prog --config $config is a usage error" test $? -eq 2
        check "which says what it is" grep -qE "'$config' is a (FIFO|character device|directory), not a regular file" "$tmp/err.txt"
    done
done

# rayview's --dialect is raytrace's: a V3 file forced to V0 fails the same way in both.
"$bin/raytrace" "$src/scenes/v3_torus.ray" --dialect v0 -q -o "$tmp/dv.png" 2>"$tmp/rt_err.txt"
check "raytrace --dialect v0 refuses a V3 file" test $? -eq 1
if [ -x "$bin/rayview" ]; then
    DISPLAY= WAYLAND_DISPLAY= "$bin/rayview" "$src/scenes/v3_torus.ray" --dialect v0 2>"$tmp/rv_err.txt"
    check "rayview --dialect v0 refuses it too" test $? -eq 1
    check "with raytrace's message" grep -qxF "$(cat "$tmp/rt_err.txt")" "$tmp/rv_err.txt"
fi
# rayview says it is out of memory as raytrace does (headless).
if [ -x "$bin/rayview" ]; then
    DISPLAY= WAYLAND_DISPLAY= check_out_of_memory "rayview out of memory" \
        "rayview: error: out of memory while rendering $scene" \
        "$bin/rayview" "$scene" --width 20000 --height 20000 --max-pixels 400000000
fi

for prog in raytrace rayview raygen raymerge imgdiff raycompare; do
    [ -x "$bin/$prog" ] || continue
    # With what it requires, so the unknown flag is the one error.
    eval "DISPLAY= '$bin/$prog' ${needs[$prog]} --no-such-flag" >/dev/null 2>"$tmp/err.txt"
    check "$prog: an unknown flag exits 2" test $? -eq 2
    check "$prog: and names it" grep -q -- "--no-such-flag" "$tmp/err.txt"
    check "$prog --version" grep -qE "^$prog [0-9]+\.[0-9]+\.[0-9]+ \(git " <("$bin/$prog" --version)
done
summary "flags"
