// NOT Apple's header: sysctlbyname as macOS's SDK declares it (sys/sysctl.h), for the syntax check of
// cpp/src/parallel/machine_probe_macos.cpp on Linux (`make test-libcxx`), whose glibc has no sys/sysctl.h.
#pragma once
#include <stddef.h>

extern "C" int sysctlbyname(const char* name, void* oldp, size_t* oldlenp, void* newp, size_t newlen);
