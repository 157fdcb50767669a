#!/usr/bin/env bash
# The MPI mode against one process on this machine: the showpiece at W x H and SPP samples per
# pixel (default 1920 1080 64, the issue's size: about 4 minutes a run on 2 cores), as one
# process (1 and 2 threads) and under mpirun (1 rank, 2 ranks = 1 worker, 3 ranks = 2 workers
# of 1 thread; --bind-to none: OpenMPI binds a rank to one core by default). Prints time, speed-up and efficiency against one thread, and the bytes of
# results the workers sent. Every image is checked against the one-process render (cmp).
# usage: bench/mpi_scaling.sh BUILD_DIR [W H SPP]
set -eu
bin="$1/app"
w=${2:-1920} h=${3:-1080} spp=${4:-64}
scene="$(dirname "$0")/../scenes/showpiece.ray"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
size=(--width "$w" --height "$h" --spp "$spp")
seconds() {  # seconds OUT CMD...: wall time of CMD, its output in OUT.txt
    local out="$1"
    shift
    local t0 t1
    t0=$(date +%s.%N)
    "$@" >"$out.txt" 2>&1
    t1=$(date +%s.%N)
    echo "$t1 - $t0" | bc -l
}
printf '| run | processes x threads | seconds | speed-up | efficiency | result bytes | image |\n'
printf '|---|---|---|---|---|---|---|\n'
t1=$(seconds "$tmp/one1" "$bin/raytrace" "$scene" "${size[@]}" --threads 1 -o "$tmp/ref.pfm")
row() {  # row NAME LAYOUT CORES SECONDS OUT
    local bytes
    bytes=$(sed -n 's/.*tiles of 32x32, \([0-9.]*\) MB of results/\1 MB/p' "$5.txt")
    local same="same"
    cmp -s "$tmp/ref.pfm" "$5.pfm" || same="DIFFERENT"
    printf '| %s | %s | %.2f | %.2f | %.0f%% | %s | %s |\n' "$1" "$2" "$4" \
        "$(echo "$t1 / $4" | bc -l)" "$(echo "100 * $t1 / $4 / $3" | bc -l)" "${bytes:--}" "$same"
}
cp "$tmp/ref.pfm" "$tmp/one1.pfm"
row "raytrace" "1 x 1" 1 "$t1" "$tmp/one1"
t=$(seconds "$tmp/one2" "$bin/raytrace" "$scene" "${size[@]}" --threads 2 -o "$tmp/one2.pfm")
row "raytrace" "1 x 2" 2 "$t" "$tmp/one2"
if [ -x "$bin/raytrace-mpi" ] && command -v mpirun >/dev/null; then
    t=$(seconds "$tmp/m1" mpirun -n 1 --bind-to none "$bin/raytrace-mpi" "$scene" "${size[@]}" --threads 2 -o "$tmp/m1.pfm")
    row "mpirun -n 1" "1 rank x 2" 2 "$t" "$tmp/m1"
    t=$(seconds "$tmp/m2" mpirun -n 2 --bind-to none "$bin/raytrace-mpi" "$scene" "${size[@]}" --threads 2 -o "$tmp/m2.pfm")
    row "mpirun -n 2" "1 worker x 2" 2 "$t" "$tmp/m2"
    t=$(seconds "$tmp/m3" mpirun -n 3 --oversubscribe --bind-to none "$bin/raytrace-mpi" "$scene" "${size[@]}" --threads 1 -o "$tmp/m3.pfm")
    row "mpirun -n 3" "2 workers x 1" 2 "$t" "$tmp/m3"
else
    echo "(raytrace-mpi or mpirun missing: the MPI rows are skipped)"
fi
