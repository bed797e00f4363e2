// Scratch, not part of the build: the factorization's dtrsm (X L^T = R, L a panel's diagonal block, R the rows
// below it) by OpenBLAS in one call, blocked by nb columns (dtrsm on each block, dgemm for the columns after it),
// and a plain column loop; one thread, operands reused hot in cache; the largest difference from OpenBLAS's result.
//   g++ -O3 -o blocked_trsm blocked_trsm.cpp -lopenblas -llapacke && ./blocked_trsm
#include <cblas.h>
#include <lapacke.h>
#include <chrono>
#include <cstdio>
#include <cmath>
#include <vector>
#include <random>
#include <algorithm>
extern "C" void openblas_set_num_threads(int);
using clk = std::chrono::steady_clock;
// X L^T = R, L w x w lower (ld w), R h x w col-major (ld h)
void blocked(int h, int w, const double* L, double* R, int nb) {
  for (int j0 = 0; j0 < w; j0 += nb) {
    int b = std::min(nb, w - j0);
    cblas_dtrsm(CblasColMajor, CblasRight, CblasLower, CblasTrans, CblasNonUnit, h, b, 1.0, L + j0 + j0 * w, w, R + j0 * h, h);
    int rest = w - j0 - b;
    if (rest > 0)
      cblas_dgemm(CblasColMajor, CblasNoTrans, CblasTrans, h, rest, b, -1.0, R + j0 * h, h, L + (j0 + b) + j0 * w, w, 1.0, R + (j0 + b) * h, h);
  }
}
// hand: column-oriented substitution, rows in tiles, vectorized over rows
__attribute__((target_clones("arch=x86-64-v3", "default")))
void hand(int h, int w, const double* L, double* R) {
  const int TR = 64;
  for (int r0 = 0; r0 < h; r0 += TR) {
    int nr = std::min(TR, h - r0);
    for (int j = 0; j < w; ++j) {
      double* xj = R + j * (size_t)h + r0;
      const double inv = 1.0 / L[j + j * w];
      for (int i = 0; i < nr; ++i) xj[i] *= inv;
      for (int k = j + 1; k < w; ++k) {
        const double l = L[k + j * w];
        double* xk = R + k * (size_t)h + r0;
        for (int i = 0; i < nr; ++i) xk[i] -= l * xj[i];
      }
    }
  }
}
int main() {
  openblas_set_num_threads(1);
  int sizes[][2] = {{90,12},{200,24},{400,57},{800,117},{1500,240},{3000,256}};
  std::mt19937 rng(1); std::uniform_real_distribution<double> U(-1,1);
  for (auto& s : sizes) {
    int h = s[0], w = s[1];
    std::vector<double> A(w*w), L(w*w, 0.0), R0((size_t)h*w), R((size_t)h*w), Rref;
    for (int i=0;i<w;i++) for(int j=0;j<w;j++) A[i+j*w] = 0.01*U(rng);
    std::vector<double> S(w*w, 0.0);
    for (int i=0;i<w;i++) for(int j=0;j<w;j++){ double t=0; for(int k=0;k<w;k++) t+=A[i+k*w]*A[j+k*w]; S[i+j*w]=t + (i==j? 1.0:0.0);} 
    L=S; LAPACKE_dpotrf(LAPACK_COL_MAJOR,'L',w,L.data(),w);
    for (auto& x:R0) x=U(rng);
    auto run=[&](auto f){ int reps = std::max(5, int(3e8/(double(h)*w*w))); double best=1e9; for(int t=0;t<3;t++){ auto a=clk::now(); for(int r=0;r<reps;r++){ R=R0; f(); } double el=std::chrono::duration<double>(clk::now()-a).count()/reps; best=std::min(best,el);} 
      // subtract copy time
      auto a=clk::now(); for(int r=0;r<reps;r++){ R=R0; } double cp=std::chrono::duration<double>(clk::now()-a).count()/reps; return best-cp; };
    double t0=run([&]{ cblas_dtrsm(CblasColMajor,CblasRight,CblasLower,CblasTrans,CblasNonUnit,h,w,1.0,L.data(),w,R.data(),h); }); Rref=R;
    double fl = double(h)*w*w;
    printf("h %4d w %3d: openblas %8.1f us %5.1f GF/s", h, w, t0*1e6, fl/t0/1e9);
    for (int nb : {16, 32, 64}) { double t=run([&]{ blocked(h,w,L.data(),R.data(),nb);}); double e=0; for(size_t i=0;i<R.size();i++) e=std::max(e,std::fabs(R[i]-Rref[i])); printf(" | nb%d %5.1f GF/s (d %.0e)", nb, fl/t/1e9, e); }
    double t=run([&]{ hand(h,w,L.data(),R.data());}); double e=0; for(size_t i=0;i<R.size();i++) e=std::max(e,std::fabs(R[i]-Rref[i]));
    printf(" | hand %5.1f GF/s (d %.0e)\n", fl/t/1e9, e);
  }
}
