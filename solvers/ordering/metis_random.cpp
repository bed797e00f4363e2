#include "solvers/ordering/metis_random.h"

#include <cstdint>
#include <cstdlib>
#include <cstring>

#include <dlfcn.h>

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

namespace db {

bool metis_draws_per_thread() {
  static const bool ours = ::dlsym(RTLD_DEFAULT, "rand") == reinterpret_cast<void*>(&::rand);
  return ours;
}

}  // namespace db
