// Compiles the kernels between RT_ISA_BEGIN and RT_ISA_END for one instruction set, in namespace
// rt::RT_ISA (rt::sse2, rt::avx2, rt::avx512). A translation unit defines RT_ISA_AVX2 or
// RT_ISA_AVX512 (or neither: the baseline) and then includes the kernel headers (walk4.h, walk8.h,
// triangle_kernel.h, walks.h), so each kernel has one source and one copy per instruction set.
//
// The translation unit itself is compiled for baseline x86-64: only the functions defined inside
// the region get the target attribute (a GCC pragma, or clang's attribute push). Standard library
// and GLM code stays baseline and may be inlined into a kernel, never the reverse, so no function
// compiled for AVX2 can be merged by the linker into code that runs on an older CPU. The whole
// project is compiled with -ffp-contract=off: no multiply and add are fused into an FMA, so the
// kernels do the same arithmetic, and find the same hits, under every instruction set. The
// AVX-512 kernels keep to 256-bit registers (prefer-vector-width here, and for copies the
// flags in core/CMakeLists.txt): what they gain is AVX-512's instructions, not its width.
#pragma once

// Not formatted: a _Pragma takes one string literal, which clang-format would split.
// clang-format off
#if defined(RT_ISA_AVX512)
#define RT_ISA avx512
#if defined(__clang__)
#define RT_ISA_BEGIN _Pragma("clang attribute push(__attribute__((target(\"avx512f,avx512vl,avx512bw,avx512dq,avx2,fma,bmi,bmi2,lzcnt,popcnt\"))), apply_to = function)") namespace rt::avx512 {
#define RT_ISA_END } _Pragma("clang attribute pop")
#else
#define RT_ISA_BEGIN _Pragma("GCC push_options") _Pragma("GCC target(\"avx512f,avx512vl,avx512bw,avx512dq,avx2,fma,bmi,bmi2,lzcnt,popcnt,prefer-vector-width=256\")") namespace rt::avx512 {
#define RT_ISA_END } _Pragma("GCC pop_options")
#endif
#elif defined(RT_ISA_AVX2)
#define RT_ISA avx2
#if defined(__clang__)
#define RT_ISA_BEGIN _Pragma("clang attribute push(__attribute__((target(\"avx2,fma,bmi,bmi2,lzcnt,popcnt\"))), apply_to = function)") namespace rt::avx2 {
#define RT_ISA_END } _Pragma("clang attribute pop")
#else
#define RT_ISA_BEGIN _Pragma("GCC push_options") _Pragma("GCC target(\"avx2,fma,bmi,bmi2,lzcnt,popcnt\")") namespace rt::avx2 {
#define RT_ISA_END } _Pragma("GCC pop_options")
#endif
#else
#define RT_ISA sse2
#define RT_ISA_SSE2 1
#define RT_ISA_BEGIN namespace rt::sse2 {
#define RT_ISA_END }
#endif
// clang-format on
