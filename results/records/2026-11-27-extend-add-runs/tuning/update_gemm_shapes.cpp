// The shapes of the update matrix's dgemm calls (front.cpp's form_update: C -= A B^T, A and B rows of one factor
// panel with its leading dimension, C an update panel), each called repeatedly on the same operands, hot in cache.
// One thread. Scratch, not part of the build:
//   g++ -O2 -o update_gemm_shapes update_gemm_shapes.cpp -lopenblas && ./update_gemm_shapes
#include <cblas.h>
#include <chrono>
#include <cstdio>
#include <vector>
extern "C" void openblas_set_num_threads(int);
int main() {
  openblas_set_num_threads(1);
  int cases[][3] = {{300,256,40},{600,256,60},{1000,256,117},{2000,256,240},{3000,256,256},{1500,144,100},{128,256,256},{400,200,60}};
  for (auto& c : cases) {
    int m=c[0], n=c[1], k=c[2]; int lda = m + n + 50;
    std::vector<double> A((size_t)lda*k, 0.5), C((size_t)m*n, 0.1);
    int reps = std::max(3, int(2e9/(2.0*m*n*k)));
    auto a=std::chrono::steady_clock::now();
    for(int r=0;r<reps;r++) cblas_dgemm(CblasColMajor,CblasNoTrans,CblasTrans,m,n,k,-1.0,A.data()+n,lda,A.data(),lda,1.0,C.data(),m);
    double t=std::chrono::duration<double>(std::chrono::steady_clock::now()-a).count()/reps;
    printf("m %5d n %4d k %4d: %6.1f GF/s\n", m,n,k, 2.0*m*n*k/t/1e9);
  }
}
