// SuiteSparse's allocations through the huge-page wrappers (solvers/ordering/suitesparse_memory.h): they must
// still be the C library's blocks with the C library's semantics (calloc zeroes, realloc keeps the contents,
// free takes them back), on either side of the size from which they are advised.
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include <SuiteSparse_config.h>
#include <gtest/gtest.h>

#include "solvers/ordering/suitesparse_memory.h"

TEST(SuiteSparseMemory, WrappersKeepTheCLibrarySemantics) {
  db::use_huge_pages_in_suitesparse();
  db::use_huge_pages_in_suitesparse();  // once per process: a second call changes nothing
  EXPECT_NE(SuiteSparse_config.malloc_func, &std::malloc);
  EXPECT_NE(SuiteSparse_config.calloc_func, &std::calloc);
  for (const std::size_t count : {std::size_t(1000), std::size_t(3) << 20}) {  // 8 KB and 24 MB of doubles
    // calloc: zeroed (the large block is zeroed after the advice, not by the C library).
    auto* z = static_cast<double*>(SuiteSparse_calloc(count, sizeof(double)));
    ASSERT_NE(z, nullptr);
    for (std::size_t i = 0; i < count; i += 511) ASSERT_EQ(z[i], 0.0) << i;
    ASSERT_EQ(z[count - 1], 0.0);
    for (std::size_t i = 0; i < count; ++i) z[i] = double(i);
    // realloc to twice the size: the contents kept.
    int ok = 0;
    auto* r = static_cast<double*>(SuiteSparse_realloc(2 * count, count, sizeof(double), z, &ok));
    ASSERT_TRUE(ok);
    for (std::size_t i = 0; i < count; i += 257) ASSERT_EQ(r[i], double(i)) << i;
    ASSERT_EQ(r[count - 1], double(count - 1));
    r[2 * count - 1] = 1.0;  // the grown part is writable
    SuiteSparse_free(r);
    auto* m = static_cast<double*>(SuiteSparse_malloc(count, sizeof(double)));
    ASSERT_NE(m, nullptr);
    m[0] = m[count - 1] = 2.0;
    SuiteSparse_free(m);
  }
  // An impossible size: no block, no overflowed small block.
  EXPECT_EQ(SuiteSparse_config.calloc_func(SIZE_MAX / 2, 4), nullptr);
}
