// The bundle's build (CMakePresets.json "bundle") includes this in every file: the check then runs
// on glibc 2.34 and newer (RHEL 9, Ubuntu 22.04), not only on the 2.36 it was built with. glibc
// 2.35 gave hypot a new symbol version; the old one (every glibc on x86-64) computes the same.
#pragma once
#if defined(__x86_64__) && defined(__linux__)
__asm__(".symver hypot,hypot@GLIBC_2.2.5");
#endif
