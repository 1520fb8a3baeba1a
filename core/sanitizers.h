// sanitizers.h — PMC_UNDER_TSAN is defined in ThreadSanitizer builds (gcc's
// __SANITIZE_THREAD__ or clang's __has_feature), for the few places that
// keep uninstrumented thread pools out of TSan's way (scripts/sanitize).
#pragma once

#if defined(__SANITIZE_THREAD__)
#define PMC_UNDER_TSAN 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define PMC_UNDER_TSAN 1
#endif
#endif
