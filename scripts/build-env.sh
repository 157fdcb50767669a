# Sourced by the scripts that configure a build tree (run.sh, test.sh, build-web.sh): Ninja as
# CMake's generator when it is installed (install-deps.sh installs it; it keeps both cores busy to
# the end of a build, where make leaves one idle behind the long files). A tree configured before
# keeps its generator, and a CMAKE_GENERATOR of the user's own is left alone.
if [ -z "${CMAKE_GENERATOR:-}" ] && command -v ninja >/dev/null; then
    export CMAKE_GENERATOR=Ninja
fi
# ccache, when installed, as the compilers' launcher of a new tree: a repeated build (a developer's
# runs of the test command, another clone on the same machine) compiles only what changed. The
# paths are taken relative to the clone (CCACHE_BASEDIR), so that two clones share the cache. A
# clean clone on a new machine builds as before; RT_NO_CCACHE=1 leaves it out.
if [ -z "${CMAKE_CXX_COMPILER_LAUNCHER:-}" ] && [ "${RT_NO_CCACHE:-0}" != 1 ] &&
    command -v ccache >/dev/null; then
    export CMAKE_CXX_COMPILER_LAUNCHER=ccache CCACHE_BASEDIR="$PWD" CCACHE_NOHASHDIR=1
fi
