// Scratch (not part of the build): form_update's products over a factorization's supernodes (rows, columns as
// DB_DUMP_SUPERNODES writes them), one thread: per 128-column update panel, dsyrk on its diagonal block + dgemm
// below (as solvers/multifrontal/front.cpp), against one dgemm over the panel's whole height (the diagonal block's
// upper triangle computed and never read); MINBELOW: panels with fewer rows below keep dsyrk + dgemm.
//   g++ -O2 -o update_one_gemm update_one_gemm.cpp -lopenblas && ./update_one_gemm SUPERNODES.txt MINBELOW
#include <cblas.h>
#include <chrono>
#include <cstdio>
#include <vector>
#include <algorithm>
extern "C" void openblas_set_num_threads(int);
static double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }
int main(int argc, char** argv) {
  openblas_set_num_threads(1);
  std::vector<std::pair<int,int>> sn; int m, n;
  FILE* f = fopen(argv[1], "r"); while (fscanf(f, "%d %d", &m, &n) == 2) sn.push_back({m, n}); fclose(f);
  int minbelow = argc > 2 ? atoi(argv[2]) : 0;
  size_t maxB = 0, maxU = 0;
  for (auto [m, n] : sn) { maxB = std::max(maxB, size_t(m) * std::min(n, 256)); maxU = std::max(maxU, size_t(m - n) * 128); }
  std::vector<double> B(maxB, 0.001), U(maxU * 64, 0.0);
  const int K = 128, P = 256;
  for (int rep = 0; rep < 3; ++rep) for (int mode = 0; mode < 2; ++mode) {
    double t = now(); size_t off = 0;
    for (auto [m, n] : sn) {
      int nr = m - n; if (nr <= 0) continue;
      for (int p0 = 0; p0 < n; p0 += P) {
        int wp = std::min(P, n - p0), ldp = m - p0 - wp;  // panel rect height
        const double* Bp = B.data() + (n - p0 - wp);      // rows below the supernode
        for (int u0 = 0; u0 < nr; u0 += K) {
          int wu = std::min(K, nr - u0), ldu = nr - u0, below = ldu - wu;
          double* C = U.data() + off; off = (off + size_t(ldu) * wu) % (maxU * 63);
          if (mode == 0 || below < minbelow) {
            cblas_dsyrk(CblasColMajor, CblasLower, CblasNoTrans, wu, wp, -1.0, Bp + u0, ldp, 1.0, C, ldu);
            if (below > 0) cblas_dgemm(CblasColMajor, CblasNoTrans, CblasTrans, below, wu, wp, -1.0, Bp + u0 + wu, ldp, Bp + u0, ldp, 1.0, C + wu, ldu);
          } else {
            cblas_dgemm(CblasColMajor, CblasNoTrans, CblasTrans, ldu, wu, wp, -1.0, Bp + u0, ldp, Bp + u0, ldp, 1.0, C, ldu);
          }
        }
      }
    }
    printf("mode %s minbelow %d: %.3f s\n", mode ? "merged" : "syrk+gemm", minbelow, now() - t); fflush(stdout);
  }
}
