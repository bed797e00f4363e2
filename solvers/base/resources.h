#pragma once
//! Process resource readings (Linux /proc).
#include <cstddef>
#include <functional>
#include <vector>

namespace db {

//! Peak resident set size of this process so far, bytes (VmHWM).
std::size_t peak_rss_bytes();
//! Current resident set size, bytes (VmRSS).
std::size_t current_rss_bytes();
//! Physical memory of the machine, bytes.
std::size_t physical_memory_bytes();

//! Threads for the project's own parallel loops (structured assembly): DEFORMBENCH_THREADS when set,
//! else the hardware threads.
int worker_threads();

//! CPUs this process may run on (its affinity mask; at least 1): the most threads that can run at once.
int available_cores();

//! Runs fn(0) .. fn(threads - 1) each on a thread of its own (fn(0) on the caller's) and joins them; the first
//! exception any of them throws is rethrown after all have finished. For measuring what threads do at the same
//! time (machine rates); computations use run_tasks.
void run_on_threads(int threads, const std::function<void(int)>& fn);

//! Runs the independent tasks fn(0) .. fn(tasks - 1) on the caller's thread and up to tasks - 1 helper threads,
//! each thread claiming the next unclaimed task; returns when every task has finished. The caller waits only for
//! tasks a helper has claimed, never for a helper that has not started yet: where another process holds a core,
//! a new thread may wait a whole scheduler slice (milliseconds) for it, and the caller does that share itself
//! meanwhile. Helpers are plain detached threads rather than an OpenMP pool, which would keep spinning after the
//! region and slow the BLAS threads that follow. Tasks must not wait for each other; each must compute the same
//! whichever thread runs it (then the results do not depend on thread timing). The first exception a task
//! throws is rethrown; tasks not yet claimed then do not run.
void run_tasks(int tasks, const std::function<void(int)>& fn);

//! [0, n) cut into contiguous ranges of at least `grain` items, at most worker_threads() of them, and fn(lo, hi)
//! run for each by run_tasks. The ranges depend on the thread count only: per-item results, or per-range
//! partials combined in range order, are the same whatever the thread timing.
void run_ranges(int n, int grain, const std::function<void(int lo, int hi)>& fn);

//! Columns [first, last) of a compressed-column pattern (`colptr`) cut into `parts` ranges of about equal entries,
//! for threads that each take one: parts + 1 ascending column boundaries from first to last.
std::vector<int> balanced_columns(const int* colptr, int first, int last, int parts);

//! Asks the kernel to back the whole 2 MB pages inside [p, p + bytes) with transparent huge pages before they
//! are first touched (no-op where unsupported). Why: first-touch faults on 4 KB pages of a 100 MB matrix cost
//! tens of milliseconds of a build.
void advise_huge_pages(void* p, std::size_t bytes);

}  // namespace db
