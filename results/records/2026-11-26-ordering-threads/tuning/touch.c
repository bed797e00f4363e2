// Scratch: first-touch cost of anonymous memory on this machine (4 KB pages, or THP with an argument), 1 GB,
// four rounds. gcc -O2 -o touch touch.c && ./touch && ./touch huge
#include <sys/mman.h>
#include <stdio.h>
#include <string.h>
#include <time.h>
static double now(){struct timespec t; clock_gettime(CLOCK_MONOTONIC,&t); return t.tv_sec+1e-9*t.tv_nsec;}
int main(int argc,char**argv){ size_t B=(size_t)1<<30; int huge=argc>1;
 for(int r=0;r<4;++r){ char*p=mmap(0,B,PROT_READ|PROT_WRITE,MAP_PRIVATE|MAP_ANONYMOUS,-1,0); if(huge) madvise(p,B,MADV_HUGEPAGE);
  double t=now(); for(size_t i=0;i<B;i+=4096) p[i]=1; double t1=now()-t; t=now(); memset(p,0,B); double t2=now()-t;
  printf("%s round %d first-touch %.3f s (%.2f GB/s) then memset %.3f s\n",huge?"huge":"4k",r,t1,1/t1,t2); munmap(p,B);} }
