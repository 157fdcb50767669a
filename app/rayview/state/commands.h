// The script's commands (rayview --script; the list: rayview --help), run on the viewer's
// state as the panels, the keys and the mouse run them, through the same verbs: the camera and
// the lights, the timeline, the comparison, the files, the views. No GL: the window's own
// commands (wait-spp, wait-jobs, wait-compare, screenshot) stay with the script runner
// (ui/script.h), and the tests run these headless.
#pragma once

#include <optional>
#include <string>

#include "state/run_options.h"
#include "state/viewer.h"

namespace rt::view {

/// Runs one command of a script on `v`. Returns what the run prints for it ("rayview: frame
/// F: ..." lines, "" for most), or nothing for a command it does not know (the runner's own).
/// Throws std::runtime_error, naming the command, for a bad argument or a command that fails
/// (a file that does not save, nothing to undo).
std::optional<std::string> run_command(ViewerState& v, const ScriptLine& l);

/// Argument i of a script line as a number in [lo, hi], or as a whole number; throws naming the
/// command otherwise (a non-finite or out-of-range value never reaches a setting).
double command_number(const ScriptLine& l, size_t i, double lo, double hi);
int command_whole(const ScriptLine& l, size_t i, int lo, int hi);

}  // namespace rt::view
