// The competitor processes of the pool's tests (competitors.h).
#include "competitors.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <string>

#ifdef _WIN32
#include "parallel/windows.h"
#else
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>
#endif

namespace bdinterp::testing {
namespace {
constexpr const char* kChildVariable = "BDINTERP_TEST_COMPETITOR";

// Spins for at most 30 s, or (POSIX) until the parent is gone.
void spin() {
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(30);
#ifndef _WIN32
  const pid_t parent = getppid();
#endif
  for (long k = 0;; ++k) {
    if ((k & 0xfffff) != 0) continue;
    if (std::chrono::steady_clock::now() > until) return;
#ifndef _WIN32
    if (getppid() != parent) return;
#endif
  }
}
}  // namespace

#ifdef _WIN32
Competitors::Competitors(int processes) {
  char exe[MAX_PATH];
  if (GetModuleFileNameA(nullptr, exe, MAX_PATH) == 0) return;
  const std::string line = std::string("\"") + exe +
                           "\" --gtest_filter=Competitors.DISABLED_Spin --gtest_also_run_disabled_tests";
  SECURITY_ATTRIBUTES inherit{sizeof(SECURITY_ATTRIBUTES), nullptr, TRUE};
  // The children's test report would interleave with this one's.
  HANDLE nul = CreateFileA("NUL", GENERIC_WRITE, FILE_SHARE_WRITE, &inherit, OPEN_EXISTING, 0, nullptr);
  SetEnvironmentVariableA(kChildVariable, "1");
  for (int k = 0; k < processes; ++k) {
    STARTUPINFOA start{};
    start.cb = sizeof start;
    start.dwFlags = STARTF_USESTDHANDLES;
    start.hStdInput = start.hStdOutput = start.hStdError = nul;
    PROCESS_INFORMATION child{};
    std::string args = line;  // CreateProcessA may write into its command line
    if (!CreateProcessA(exe, &args[0], nullptr, nullptr, TRUE, 0, nullptr, nullptr, &start, &child)) continue;
    CloseHandle(child.hThread);
    children_.push_back(reinterpret_cast<intptr_t>(child.hProcess));
  }
  SetEnvironmentVariableA(kChildVariable, nullptr);
  if (nul != INVALID_HANDLE_VALUE) CloseHandle(nul);
}

Competitors::~Competitors() {
  for (intptr_t h : children_) {
    TerminateProcess(reinterpret_cast<HANDLE>(h), 0);
    WaitForSingleObject(reinterpret_cast<HANDLE>(h), INFINITE);
    CloseHandle(reinterpret_cast<HANDLE>(h));
  }
}
#else
Competitors::Competitors(int processes) {
  for (int k = 0; k < processes; ++k) {
    const pid_t pid = fork();
    if (pid == 0) {
      spin();
      _exit(0);  // no atexit handlers, no test report: the parent's
    }
    if (pid > 0) children_.push_back(pid);
  }
}

Competitors::~Competitors() {
  for (intptr_t pid : children_) kill(static_cast<pid_t>(pid), SIGKILL);
  for (intptr_t pid : children_) waitpid(static_cast<pid_t>(pid), nullptr, 0);
}
#endif

// The body of a Windows competitor (run by name, with kChildVariable set); otherwise nothing.
TEST(Competitors, DISABLED_Spin) {
  if (std::getenv(kChildVariable)) spin();
}

}  // namespace bdinterp::testing
