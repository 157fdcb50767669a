#include "version.h"

#include "rt/util/isa.h"
#include "rt_version.h"  // generated at build time by cmake/version.cmake

namespace rtapp {

std::string version_text(const std::string& program, bool traces) {
    std::string s = program + " " RT_VERSION " (git " RT_GIT_COMMIT ")";
    if (traces) s += "\ninstruction set " + rt::isa_summary();
    return s;
}

}  // namespace rtapp
