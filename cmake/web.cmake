# The web build's dependencies (scripts/build-web.sh configures this through emcmake). Emscripten's toolchain searches its own sysroot only, so the header-only Debian
# packages the desktop build uses (GLM, stb, CLI11) come in through a directory of links to
# them: the same headers, not all of /usr/include, whose glibc headers would shadow the sysroot's.
# Dear ImGui is compiled from Debian's source package of the desktop's version (1.86;
# scripts/install-deps.sh fetches it into build-web-deps/), with its GLFW and OpenGL 3 back ends.

set(RT_IMGUI_SOURCE_DIR "${PROJECT_SOURCE_DIR}/build-web-deps/imgui-1.86" CACHE PATH
    "Dear ImGui 1.86's sources (Debian's source package imgui)")
if(NOT EXISTS "${RT_IMGUI_SOURCE_DIR}/imgui.cpp")
    message(FATAL_ERROR "No Dear ImGui sources in ${RT_IMGUI_SOURCE_DIR}: run "
                        "scripts/install-deps.sh (it fetches Debian's imgui 1.86 source package)")
endif()

set(_rt_host_include "${PROJECT_BINARY_DIR}/host-include")
file(MAKE_DIRECTORY "${_rt_host_include}")
foreach(dir glm stb CLI)
    if(NOT EXISTS "/usr/include/${dir}")
        message(FATAL_ERROR "/usr/include/${dir} is missing: run scripts/install-deps.sh")
    endif()
    file(CREATE_LINK "/usr/include/${dir}" "${_rt_host_include}/${dir}" SYMBOLIC)
endforeach()

add_library(glm::glm INTERFACE IMPORTED)
target_include_directories(glm::glm SYSTEM INTERFACE "${_rt_host_include}")
add_library(PkgConfig::STB INTERFACE IMPORTED)
target_include_directories(PkgConfig::STB SYSTEM INTERFACE "${_rt_host_include}/stb")
add_library(CLI11::CLI11 INTERFACE IMPORTED)
target_include_directories(CLI11::CLI11 SYSTEM INTERFACE "${_rt_host_include}")

# Every target: C++ exceptions (the library reports errors by throwing; Emscripten's prebuilt
# libraries have JavaScript-based exception support, not WebAssembly's), the SSE kernels through
# WebAssembly SIMD, and code for threads (atomics), which the single-thread program links too
# (app/web: only the threads program links with shared memory).
add_compile_options(-fexceptions -msimd128 -msse2 -pthread)
add_link_options(-fexceptions)

add_library(imgui STATIC
    ${RT_IMGUI_SOURCE_DIR}/imgui.cpp ${RT_IMGUI_SOURCE_DIR}/imgui_draw.cpp
    ${RT_IMGUI_SOURCE_DIR}/imgui_tables.cpp ${RT_IMGUI_SOURCE_DIR}/imgui_widgets.cpp
    ${RT_IMGUI_SOURCE_DIR}/backends/imgui_impl_glfw.cpp
    ${RT_IMGUI_SOURCE_DIR}/backends/imgui_impl_opengl3.cpp)
# As Debian's libimgui-dev installs them: <imgui.h> and <backends/imgui_impl_glfw.h>.
target_include_directories(imgui SYSTEM PUBLIC ${RT_IMGUI_SOURCE_DIR})
# Never one unity-build file: the OpenGL back end decides which GL it has from the macros the
# files before it would leave defined (it then calls glPolygonMode, which WebGL lacks).
set_target_properties(imgui PROPERTIES UNITY_BUILD OFF)
target_compile_options(imgui PRIVATE -sUSE_GLFW=3)
target_link_options(imgui PUBLIC -sUSE_GLFW=3 -sMIN_WEBGL_VERSION=2 -sMAX_WEBGL_VERSION=2)

# Clang also reports floats widened in assignments and calls (the viewer's ImGui floats); the
# warning is kept for what it is there for, float arithmetic widened in hot code, by GCC's
# desktop build, which compiles the same sources.
target_compile_options(rt_warnings INTERFACE -Wno-double-promotion)
