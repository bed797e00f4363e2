// Scratch (not part of the build): the same first touch of MB megabytes (huge-page advised) split over THREADS threads.
//   gcc -O2 -pthread -o touch_threads touch_threads.c && ./touch_threads 800 2
#include <stdio.h>
#include <stdlib.h>
#include <pthread.h>
#include <sys/mman.h>
#include <time.h>
static double now(){struct timespec t; clock_gettime(CLOCK_MONOTONIC,&t); return t.tv_sec+1e-9*t.tv_nsec;}
char*p; size_t n; int T;
void* w(void*a){ long k=(long)a; size_t lo=n/T*k, hi=n/T*(k+1); for(size_t i=lo;i<hi;i+=4096) p[i]=1; return 0;}
int main(int argc,char**argv){ n=(size_t)atoi(argv[1])<<20; T=atoi(argv[2]);
 p=mmap(0,n,PROT_READ|PROT_WRITE,MAP_PRIVATE|MAP_ANONYMOUS,-1,0); madvise(p,n,MADV_HUGEPAGE);
 pthread_t th[64]; double t=now(); for(long k=0;k<T;++k) pthread_create(&th[k],0,w,(void*)k); for(int k=0;k<T;++k) pthread_join(th[k],0);
 double a=now()-t; printf("%s MB %d threads: %.3f s (%.2f GB/s)\n",argv[1],T,a,n/1e9/a);}
