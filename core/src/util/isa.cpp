#include "rt/util/isa.h"

#include <cstdlib>
#include <string_view>

#include "rt/util/enum_names.h"
#include "rt/util/error.h"

namespace rt {

namespace {

bool cpu_runs(Isa isa) {
#if defined(__x86_64__) && !defined(__wasm__) && !defined(RT_SSE2_ONLY)
    __builtin_cpu_init();
    switch (isa) {
        case Isa::Sse2:
            return true;
        case Isa::Avx2:
            // __builtin_cpu_supports also checks that the OS saves the wide registers.
            return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&
                   __builtin_cpu_supports("bmi") && __builtin_cpu_supports("bmi2") &&
                   __builtin_cpu_supports("popcnt");
        case Isa::Avx512:
            return cpu_runs(Isa::Avx2) && __builtin_cpu_supports("avx512f") &&
                   __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512bw") &&
                   __builtin_cpu_supports("avx512dq");
    }
    return false;
#else
    // The web build (WebAssembly SIMD behind the SSE intrinsics), or one without the wide
    // kernels (RT_WIDE_KERNELS off).
    return isa == Isa::Sse2;
#endif
}

struct Choice {
    Isa isa = Isa::Sse2;
    bool forced = false;
    std::string error;  // RAYTRACER_ISA could not be honoured
};

std::string cpu_list() {
    std::string s;
    for (Isa i : supported_isas()) s += (s.empty() ? "" : ", ") + std::string(isa_name(i));
    return s;
}

Choice choose() {
    Choice c;
    c.isa = supported_isas().back();
    const char* env = std::getenv("RAYTRACER_ISA");
    if (!env || !*env) return c;
    const std::string_view want(env);
    for (int i = 0; i < kIsaCount; ++i) {
        const Isa isa = static_cast<Isa>(i);
        if (want != isa_name(isa)) continue;
        if (!cpu_runs(isa)) {
            c.error = "RAYTRACER_ISA=" + std::string(want) + ": this CPU cannot run it; it runs " +
                      cpu_list();
            return c;
        }
        c.isa = isa;
        c.forced = true;
        return c;
    }
    c.error = "RAYTRACER_ISA=" + std::string(want) +
              ": not an instruction set; use sse2, avx2 or avx512 (this CPU runs " + cpu_list() +
              ")";
    return c;
}

const Choice& choice() {
    static const Choice c = choose();
    return c;
}

}  // namespace

const char* isa_name(Isa isa) {
    static constexpr const char* kNames[kIsaCount] = {"sse2", "avx2", "avx512"};
    return enum_name(isa, kNames, "?");
}

std::vector<Isa> supported_isas() {
    std::vector<Isa> v;
    for (int i = 0; i < kIsaCount; ++i)
        if (cpu_runs(static_cast<Isa>(i))) v.push_back(static_cast<Isa>(i));
    return v;
}

Isa active_isa() {
    const Choice& c = choice();
    if (!c.error.empty()) throw SceneError({}, c.error);
    return c.isa;
}

const std::string& isa_error() { return choice().error; }

std::string isa_summary() {
    const Choice& c = choice();
    if (!c.error.empty()) return c.error;
    return std::string(isa_name(c.isa)) + (c.forced ? " (set by RAYTRACER_ISA; " : " (") +
           "this CPU runs " + cpu_list() + ")";
}

}  // namespace rt
