#!/usr/bin/env bash
# raytrace-mpi on this machine (loopback): 3 ranks render the showpiece and an instanced scene
# into raytrace's image bit for bit (.pfm byte for byte), and a sequence into raytrace --frames'
# frames; a worker that hangs or dies stops the
# job with a message naming the rank and the tile, and no image is written. Skipped with a
# message when OpenMPI (mpirun, raytrace-mpi) is not installed.
# usage: test_mpi.sh RAYTRACE RAYTRACE_MPI|"" SOURCE_DIR
set -u
rt="$1"
mpi="$2"
src="$3"
if [ -z "$mpi" ] || [ ! -x "$mpi" ] || ! command -v mpirun >/dev/null; then
    echo "mpi: SKIPPED: OpenMPI is not installed (scripts/install-deps.sh installs libopenmpi-dev openmpi-bin)"
    exit 0
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# OpenMPI refuses to run as root unless told; CI runs as root. Only for this test.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
run=(mpirun -n 3 --oversubscribe -x RT_MPI_FAULT)
source "$(dirname "$0")/check.sh"
size=(--width 100 --height 70 --spp 3)
for scene in showpiece groups v3_penumbra; do
    "$rt" "$src/scenes/$scene.ray" "${size[@]}" -q -o "$tmp/$scene-one.pfm"
    RT_MPI_FAULT= "${run[@]}" "$mpi" "$src/scenes/$scene.ray" "${size[@]}" -o "$tmp/$scene-mpi.pfm" \
        >"$tmp/$scene.txt" 2>&1
    check "$scene: mpirun exits 0" test $? -eq 0
    check "$scene: 3 ranks give raytrace's image bit for bit" cmp -s "$tmp/$scene-one.pfm" "$tmp/$scene-mpi.pfm"
done
check "the summary counts the ranks and tiles" grep -q "mpi       3 ranks (2 rendering), 12 tiles of 32x32" "$tmp/showpiece.txt"

# OpenEXR with AOVs: rank 0 traces the first hits of the merged render: raytrace's file.
aovs=(--exr-float --aov albedo,normal,depth,samples,variance)
"$rt" "$src/scenes/showpiece.ray" "${size[@]}" "${aovs[@]}" -q -o "$tmp/aov-one.exr"
RT_MPI_FAULT= "${run[@]}" "$mpi" "$src/scenes/showpiece.ray" "${size[@]}" "${aovs[@]}" -q \
    -o "$tmp/aov-mpi.exr"
check "exr with aovs: mpirun exits 0" test $? -eq 0
check "exr with aovs: raytrace's file byte for byte" cmp -s "$tmp/aov-one.exr" "$tmp/aov-mpi.exr"
"$rt" "$src/scenes/showpiece.ray" "${size[@]}" --progressive --aov depth -q -o "$tmp/paov-one.exr"
RT_MPI_FAULT= "${run[@]}" "$mpi" "$src/scenes/showpiece.ray" "${size[@]}" --progressive \
    --aov depth -q -o "$tmp/paov-mpi.exr"
check "progressive exr with aovs: raytrace's file" cmp -s "$tmp/paov-one.exr" "$tmp/paov-mpi.exr"
RT_MPI_FAULT= "${run[@]}" "$mpi" "$src/scenes/robot_arm.ray" --frames 2 --aov depth \
    -o "$tmp/faov_%d.exr" >/dev/null 2>"$tmp/faov.txt"
check "--frames with --aov: a usage error (2)" test $? -eq 2
check "which says so" grep -q "raytrace-mpi --frames writes no AOVs" "$tmp/faov.txt"

# A sequence: frames handed out whole, each written by rank 0, each raytrace --frames' frame.
arm="$src/scenes/robot_arm.ray"
"$rt" "$arm" --width 48 --height 36 --frames 4 --fps 3 -q -o "$tmp/rt_%d.pfm"
RT_MPI_FAULT= "${run[@]}" "$mpi" "$arm" --width 48 --height 36 --frames 4 --fps 3 -q -o "$tmp/mpi_%d.pfm"
check "a sequence: mpirun exits 0" test $? -eq 0
for k in 0 1 2 3; do
    check "frame $k is raytrace's" cmp -s "$tmp/rt_$k.pfm" "$tmp/mpi_$k.pfm"
done
# A frame that cannot be written (its name taken by a directory; on a cluster, a full disk)
# fails the job, and the frames written before it are removed, as raytrace --frames does; with
# workers and with rank 0 alone.
for n in 3 1; do
    mkdir -p "$tmp/wf$n/f_3.pfm"
    RT_MPI_FAULT= mpirun -n $n --oversubscribe "$mpi" "$arm" --width 48 --height 36 --spp 1 \
        --frames 6 -q -o "$tmp/wf$n/f_%d.pfm" >"$tmp/wf$n.txt" 2>&1
    check "$n ranks: an unwritable frame fails the job" test $? -ne 0
    check "$n ranks: it is named" grep -qF "raytrace-mpi: error: frame 3 not written (cannot write '$tmp/wf$n/f_3.pfm': it is a directory, not a regular file); " "$tmp/wf$n.txt"
    check "$n ranks: no frame of the job is left" test "$(ls -A "$tmp/wf$n")" = "f_3.pfm"
done
# A frame whose animation fails on a worker: the job fails with its message, no frame left.
printf '#key_file k.key\n#shape_sphere -1 0 0 0 1\n#joint_begin arm\n#shape_sphere -1 0 0 0 1\n#joint_end\n' >"$tmp/far.ray"
printf '#DOFS 1 arm #DURATION 1 #FRAMES 2 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1  1 0 0 0 0 1 0 0 0 0 1 0 1e305 0 0 1\n' >"$tmp/k.key"
mkdir "$tmp/fa"
RT_MPI_FAULT= "${run[@]}" "$mpi" "$tmp/far.ray" --width 8 --height 6 --spp 1 --frames 3 --fps 2 \
    -q -o "$tmp/fa/g_%d.pfm" >"$tmp/fa.txt" 2>&1
check "a worker's failed animation fails the job" test $? -ne 0
check "with the worker's message" grep -q "raytrace-mpi: error: rank [12] failed at frame 1: .*joint reaches beyond" "$tmp/fa.txt"
check "and no frame of the job is left" test -z "$(ls -A "$tmp/fa")"

# Progressive: each pass's tiles handed out; the error report, and with --spp the same image.
"$rt" "$src/scenes/showpiece.ray" "${size[@]}" --progressive -q -o "$tmp/prog-one.pfm"
RT_MPI_FAULT= "${run[@]}" "$mpi" "$src/scenes/showpiece.ray" "${size[@]}" --progressive \
    --report "$tmp/prog.csv" -o "$tmp/prog-mpi.pfm" >"$tmp/prog.txt" 2>&1
check "progressive: mpirun exits 0" test $? -eq 0
check "progressive: the image is raytrace --progressive's" cmp -s "$tmp/prog-one.pfm" "$tmp/prog-mpi.pfm"
check "progressive: the pass table" grep -q "relMSE falls as time" "$tmp/prog.txt"
check "progressive: the report has a row a pass" test "$(grep -c '^uniform,' "$tmp/prog.csv")" -eq 3
# The estimate (each pixel's even against its odd samples) from the workers' odd sums: the same
# numbers as one process's.
"$rt" "$src/scenes/showpiece.ray" "${size[@]}" --progressive --light-radius 0.3 \
    --report "$tmp/est-one.csv" -q -o "$tmp/est-one.pfm"
RT_MPI_FAULT= "${run[@]}" "$mpi" "$src/scenes/showpiece.ray" "${size[@]}" --progressive \
    --light-radius 0.3 --report "$tmp/est-mpi.csv" -q -o "$tmp/est-mpi.pfm"
check "progressive: the estimates are one process's" \
    cmp -s <(cut -d, -f3,8,9 "$tmp/est-one.csv") <(cut -d, -f3,8,9 "$tmp/est-mpi.csv")

# Faults: a worker that hangs (the tile timeout), a worker that dies.
RT_MPI_FAULT=hang:2:1 "${run[@]}" "$mpi" "$src/scenes/showpiece.ray" "${size[@]}" \
    --tile-timeout 5 -o "$tmp/hang.pfm" >"$tmp/hang.txt" 2>&1
check "a hanging worker fails the job" test $? -ne 0
check "a hanging worker is named with its tile" grep -q "raytrace-mpi: error: rank 2 did not finish tile [0-9]* (pixels .*) within 5 s" "$tmp/hang.txt"
check "a hanging worker: no image" test ! -e "$tmp/hang.pfm"
RT_MPI_FAULT=die:1:0 "${run[@]}" "$mpi" "$src/scenes/showpiece.ray" "${size[@]}" \
    -o "$tmp/die.pfm" >"$tmp/die.txt" 2>&1
check "a dying worker fails the job" test $? -ne 0
check "a dying worker is named with its tile" grep -q "raytrace-mpi: error: the job was stopped: rank 1 (pid [0-9]*) died; under way: .*rank 1 had tile" "$tmp/die.txt"
check "a dying worker: no image" test ! -e "$tmp/die.pfm"
# A sequence whose worker dies after frames were written: they are removed.
RT_MPI_FAULT=die:1:1 "${run[@]}" "$mpi" "$arm" --width 48 --height 36 --frames 8 -q \
    -o "$tmp/dief_%d.pfm" >"$tmp/dief.txt" 2>&1
check "a sequence's dying worker fails the job" test $? -ne 0
check "a sequence's dying worker is named with its frame" grep -q "rank 1 (pid [0-9]*) died; under way: .*rank 1 had frame [0-9]" "$tmp/dief.txt"
check "a sequence's frames written before are removed" bash -c "! ls '$tmp'/dief_* 2>/dev/null && grep -q 'written so far w[a-z]* removed' '$tmp/dief.txt'"
# A worker that cannot load the scene (here: another path; on a cluster, a file missing on its
# node) stops the job with its own error.
RT_MPI_FAULT= mpirun -n 1 --oversubscribe "$mpi" "$src/scenes/showpiece.ray" "${size[@]}" \
    -o "$tmp/load.pfm" : -n 2 "$mpi" "$tmp/not-on-this-node.ray" "${size[@]}" -o "$tmp/load.pfm" \
    >"$tmp/load.txt" 2>&1
check "a worker's load error fails the job" test $? -ne 0
check "a worker's load error is printed with its rank" grep -q "raytrace-mpi: error: rank [12] could not load the scene: .*not-on-this-node.ray: error: cannot open" "$tmp/load.txt"
check "a worker's load error: no image" test ! -e "$tmp/load.pfm"
RT_MPI_FAULT= "${run[@]}" "$mpi" "$src/scenes/showpiece.ray" --spp 4 -o "$tmp/p.part" >"$tmp/p.txt" 2>&1
check "an unsupported mode is a usage error" grep -q "raytrace-mpi renders an image (also --progressive) or --frames" "$tmp/p.txt"
check "which points at raytrace-mpi's own help" grep -qx "(see raytrace-mpi --help)" "$tmp/p.txt"
# --tile-timeout: seconds, more than 0 and at most a week; anything else (1e10 and inf were a
# float-to-int overflow) is a usage error.
for t in 1e10 inf 5x 604801; do
    RT_MPI_FAULT= mpirun -n 1 "$mpi" "$src/scenes/showpiece.ray" --tile-timeout "$t" \
        -o "$tmp/tt.png" >"$tmp/tt.txt" 2>&1
    check "--tile-timeout $t exits 2" test $? -eq 2
    check "--tile-timeout $t: says its range" grep -q "tile-timeout takes seconds, more than 0 and at most 604800" "$tmp/tt.txt"
done
check "no image after them" test ! -e "$tmp/tt.png"

summary "mpi"
