# The end-to-end scripts' checker (sourced): `check NAME CONDITION...` runs CONDITION, counts a
# pass or prints "FAIL: NAME"; a script ends with `summary WHAT`, which prints the counts and
# fails when a check did.
fails=0
passes=0
check() {
    local name="$1"
    shift
    if "$@"; then
        passes=$((passes + 1))
    else
        echo "FAIL: $name"
        fails=$((fails + 1))
    fi
}
summary() {
    echo "$passes passed, $fails failed${1:+ ($1)}"
    test "$fails" -eq 0
}
# xrun CMD...: CMD under a virtual display, with CMD's own exit status (tests/app/xrun.sh).
xrun() {
    "$(dirname "${BASH_SOURCE[0]}")/xrun.sh" "$@"
}
# check_out_of_memory NAME MESSAGE CMD...: CMD, whose address space is capped at 1 GB, exits 1
# with the exact line MESSAGE on stderr (not a bare std::bad_alloc). Skipped for a sanitizer build
# of CMD, whose shadow memory needs an address space without a cap.
check_out_of_memory() {
    local name="$1" message="$2" err
    shift 2
    grep -q -e __asan_init -e __tsan_init "$1" && return 0
    err=$(mktemp)
    (ulimit -v 1000000 && exec "$@") >/dev/null 2>"$err"
    check "$name: exits 1" test $? -eq 1
    check "$name: says so" grep -qxF "$message" "$err"
    rm -f "$err"
}
