#pragma once
// OROGEN_TEST_ASAN is defined when the test is built with AddressSanitizer (GCC's __SANITIZE_ADDRESS__ or
// clang's __has_feature): tests that time or size their work by the build use it.
#if defined(__SANITIZE_ADDRESS__)
#define OROGEN_TEST_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define OROGEN_TEST_ASAN 1
#endif
#endif
