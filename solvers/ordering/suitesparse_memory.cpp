#include "solvers/ordering/suitesparse_memory.h"

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <mutex>

#include <SuiteSparse_config.h>

#include "solvers/base/resources.h"

namespace db {
namespace {

// Below this a block holds at most one whole 2 MB page: advice would buy little and split the heap's mappings.
constexpr std::size_t kAdviseBytes = std::size_t(4) << 20;

void* advised_malloc(std::size_t bytes) {
  void* p = std::malloc(bytes);
  if (p && bytes >= kAdviseBytes) advise_huge_pages(p, bytes);
  return p;
}

//! calloc's zeroing would touch the pages before the advice: allocate, advise, then zero.
void* advised_calloc(std::size_t count, std::size_t size) {
  if (size != 0 && count > SIZE_MAX / size) return nullptr;
  const std::size_t bytes = count * size;
  if (bytes < kAdviseBytes) return std::calloc(count, size);
  void* p = advised_malloc(bytes);
  if (p) std::memset(p, 0, bytes);
  return p;
}

//! The pages already touched keep their size; the rest of a large block is advised.
void* advised_realloc(void* old, std::size_t bytes) {
  void* p = std::realloc(old, bytes);
  if (p && bytes >= kAdviseBytes) advise_huge_pages(p, bytes);
  return p;
}

}  // namespace

void use_huge_pages_in_suitesparse() {
  static std::once_flag once;
  std::call_once(once, [] {
    SuiteSparse_config.malloc_func = advised_malloc;
    SuiteSparse_config.calloc_func = advised_calloc;
    SuiteSparse_config.realloc_func = advised_realloc;
    SuiteSparse_config.free_func = std::free;
  });
}

}  // namespace db
