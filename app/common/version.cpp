#include "version.h"

#include "rt_version.h"  // generated at build time by cmake/version.cmake

namespace rtapp {

std::string version_text(const std::string& program) {
    return program + " " RT_VERSION " (git " RT_GIT_COMMIT ")";
}

}  // namespace rtapp
