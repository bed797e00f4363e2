// Scratch, not part of the build: the update matrix's products in front.cpp's form_update, on shapes of the 104k TF
// factorization, one thread: C -= A B^T by dgemm (m rows below an update panel of 128 columns, k the supernode's
// columns) and by dsyrk (the panel's 128 x 128 diagonal block), with A and B rows of one factor panel at its
// leading dimension. C either one block reused (hot in cache) or cycling through 256 MB of blocks (from memory);
// beta 1, and beta 0 (a fresh block, which OpenBLAS zeroes first).
//   g++ -O2 -o update_shapes update_shapes.cpp -lopenblas && ./update_shapes
#include <cblas.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <vector>

extern "C" void openblas_set_num_threads(int);

int main() {
  openblas_set_num_threads(1);
  const int cases[][2] = {{300, 40}, {600, 60}, {1000, 117}, {2000, 240}};  // m, k
  const int n = 128;
  for (const auto& c : cases) {
    const int m = c[0], k = c[1], lda = m + n + 50;
    std::vector<double> A(std::size_t(lda) * k, 0.5);
    for (int syrk = 0; syrk < 2; ++syrk) {
      const int rows = syrk ? n : m;
      const std::size_t block = std::size_t(rows) * n;
      const int blocks = int((std::size_t(256) << 20) / (block * 8)) + 1;
      std::vector<double> C(block * blocks, 0.1);
      const double flops = syrk ? double(n) * n * k : 2.0 * m * n * k;
      for (double beta : {1.0, 0.0})
        for (int cycling = 0; cycling < 2; ++cycling) {
          const int reps = std::max(blocks, int(3e9 / flops));
          const auto a = std::chrono::steady_clock::now();
          for (int r = 0; r < reps; ++r) {
            double* Cr = C.data() + (cycling ? std::size_t(r % blocks) * block : 0);
            if (syrk)
              cblas_dsyrk(CblasColMajor, CblasLower, CblasNoTrans, n, k, -1.0, A.data(), lda, beta, Cr, n);
            else
              cblas_dgemm(CblasColMajor, CblasNoTrans, CblasTrans, m, n, k, -1.0, A.data() + n, lda, A.data(), lda,
                          beta, Cr, m);
          }
          const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - a).count() / reps;
          std::printf("%s m %4d n %d k %3d beta %.0f C %s: %5.1f GFlop/s\n", syrk ? "dsyrk" : "dgemm", rows, n, k,
                      beta, cycling ? "from memory" : "hot", flops / t / 1e9);
        }
    }
  }
}
