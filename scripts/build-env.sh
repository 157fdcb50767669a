# Sourced by the scripts that configure a build tree (run.sh, test.sh, build-web.sh): Ninja as
# CMake's generator when it is installed (install-deps.sh installs it; it keeps both cores busy to
# the end of a build, where make leaves one idle behind the long files). A tree configured before
# keeps its generator, and a CMAKE_GENERATOR of the user's own is left alone.
if [ -z "${CMAKE_GENERATOR:-}" ] && command -v ninja >/dev/null; then
    export CMAKE_GENERATOR=Ninja
fi
