// Which sanitizer a unit is built with, for the few places that must behave differently under
// one: RT_ASAN under AddressSanitizer, RT_TSAN under ThreadSanitizer (GCC defines
// __SANITIZE_ADDRESS__ / __SANITIZE_THREAD__, clang answers __has_feature). Both map a large
// shadow address space, so an address-space cap cannot be used under them.
#pragma once

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define RT_ASAN 1
#endif
#if __has_feature(thread_sanitizer)
#define RT_TSAN 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__) && !defined(RT_ASAN)
#define RT_ASAN 1
#endif
#if defined(__SANITIZE_THREAD__) && !defined(RT_TSAN)
#define RT_TSAN 1
#endif
