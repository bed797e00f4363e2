#include "solvers/ordering/metis_random.h"

#include <cstdint>
#include <cstdlib>
#include <cstring>

#include <dlfcn.h>
#include <signal.h>

namespace {

//! One thread's generator: glibc's random_r on a 128-byte state (TYPE_3, what glibc's rand() uses), seeded with
//! 1 on first use as a process's generator is.
struct ThreadGenerator {
  random_data data;
  char state[128];
  bool seeded = false;

  random_data& get() {
    if (!seeded) {
      std::memset(&data, 0, sizeof data);
      initstate_r(1, state, sizeof state, &data);
      seeded = true;
    }
    return data;
  }
};

thread_local ThreadGenerator generator;

}  // namespace

extern "C" int rand() noexcept {
  std::int32_t r = 0;
  random_r(&generator.get(), &r);
  return r;
}

extern "C" void srand(unsigned seed) noexcept { srandom_r(seed, &generator.get()); }

namespace {

//! Whether `address` (a return address) lies in METIS's shared library.
bool in_libmetis(const void* address) {
  Dl_info info{};
  return ::dladdr(address, &info) != 0 && info.dli_fname != nullptr && std::strstr(info.dli_fname, "libmetis") != nullptr;
}

}  // namespace

// signal() of ISO C code (glibc's __sysv_signal: a one-shot handler, the signal not blocked while it runs).
extern "C" sighandler_t __sysv_signal(int sig, sighandler_t handler) noexcept {
  struct sigaction now {};
  if (in_libmetis(__builtin_return_address(0))) {  // METIS's traps: leave the process's handlers in place
    if (::sigaction(sig, nullptr, &now) != 0) return SIG_ERR;
    return now.sa_handler;
  }
  struct sigaction sa {};
  sa.sa_handler = handler;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESETHAND | SA_NODEFER;
  if (::sigaction(sig, &sa, &now) != 0) return SIG_ERR;
  return now.sa_handler;
}

namespace db {

bool metis_on_threads() {
  static const bool ours = ::dlsym(RTLD_DEFAULT, "rand") == reinterpret_cast<void*>(&::rand) &&
                           ::dlsym(RTLD_DEFAULT, "srand") == reinterpret_cast<void*>(&::srand) &&
                           ::dlsym(RTLD_DEFAULT, "__sysv_signal") == reinterpret_cast<void*>(&::__sysv_signal);
  return ours;
}

}  // namespace db
