// The programs' --version text: the project's version and the git commit it was built from.
#pragma once

#include <string>

namespace rtapp {

/// "PROGRAM VERSION (git COMMIT)", e.g. "raytrace 0.2.0 (git 3f2a9c1d0b7e)"; the commit ends in
/// "-dirty" when the build had uncommitted changes, and is "unknown" outside a git checkout.
/// A program that traces rays (`traces`) adds a second line, "instruction set avx2 (this CPU runs
/// sse2, avx2)": the kernels it runs with (rt/util/isa.h).
std::string version_text(const std::string& program, bool traces = false);

}  // namespace rtapp
