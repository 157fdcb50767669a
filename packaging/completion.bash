# bash completion for raytrace, raytrace-mpi, rayview, raymerge, raygen and raycompare: options from the
# program's own --help (so they never go out of date), the names an option accepts, and files:
# .ray scenes for the scene, .part files for raymerge, any file after an option that takes one.
_raytracer_complete() {
    local cur=${COMP_WORDS[COMP_CWORD]} prev=${COMP_WORDS[COMP_CWORD - 1]}
    local cmd=${COMP_WORDS[0]}
    COMPREPLY=()
    case $prev in
    -o | --output | --reference | --report | --plot | --video | --screenshot | --script | --config \
        | --inspect-json | --csv | --html | --compare)
        compopt -o filenames 2>/dev/null
        mapfile -t COMPREPLY < <(compgen -f -- "$cur")
        return ;;
    --dialect) mapfile -t COMPREPLY < <(compgen -W "v0 v1 v3" -- "$cur"); return ;;
    --missing-textures) mapfile -t COMPREPLY < <(compgen -W "error checker" -- "$cur"); return ;;
    --interpolation)
        mapfile -t COMPREPLY < <(compgen -W "nearest linear catmull-rom bspline" -- "$cur")
        return ;;
    --rotation)
        mapfile -t COMPREPLY < <(compgen -W "matrix closest euler log quaternion" -- "$cur")
        return ;;
    --layout) mapfile -t COMPREPLY < <(compgen -W "both preview trace" -- "$cur"); return ;;
    --panel) mapfile -t COMPREPLY < <(compgen -W "on off" -- "$cur"); return ;;
    --aov)  # a comma-separated list: complete the last name
        local done=${cur%,*} last=${cur##*,} names="albedo normal depth samples variance"
        [[ $cur == *,* ]] || done=""
        mapfile -t COMPREPLY < <(compgen -W "$names" -P "${done:+$done,}" -- "$last")
        return ;;
    esac
    if [[ $cur == -* ]]; then
        local opts
        opts=$("$cmd" --help 2>/dev/null | grep -oE -- '(^|[ ,])--?[a-zA-Z][-a-zA-Z0-9]*' |
            sed 's/^[ ,]*//' | sort -u)
        mapfile -t COMPREPLY < <(compgen -W "$opts" -- "$cur")
        return
    fi
    # An option that takes a value other than those above: nothing to offer.
    if [[ $prev == --* ]] && "$cmd" --help 2>/dev/null | grep -qE -- "$prev [A-Z]"; then
        return
    fi
    local glob='*.ray'
    [[ ${cmd##*/} == raymerge ]] && glob='*.part'
    compopt -o filenames 2>/dev/null
    mapfile -t COMPREPLY < <(compgen -f -X "!$glob" -- "$cur"; compgen -d -- "$cur")
}
complete -F _raytracer_complete raytrace raytrace-mpi rayview raymerge raygen raycompare
