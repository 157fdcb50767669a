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
