#!/usr/bin/env bash
# xrun.sh CMD [ARG...]: runs CMD under a virtual display (xvfb-run -a, a 1280x720x24 screen) and
# exits with CMD's own status. xvfb-run's status may be its own: on a loaded machine it can fail
# to remove its temporary files after CMD ended and exit 5 ("problem while cleaning up").
# 127 when CMD never ran (no display could be started).
RT_XRUN_RC=$(mktemp)
export RT_XRUN_RC
trap 'rm -f "$RT_XRUN_RC"' EXIT
echo 127 >"$RT_XRUN_RC"
xvfb-run -a -s "-screen 0 1280x720x24" bash -c '"$@"; echo $? >"$RT_XRUN_RC"' xrun "$@"
exit "$(cat "$RT_XRUN_RC")"
