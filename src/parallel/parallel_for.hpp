// Worker threads of a step, from OpenMP's pool. Every parallel loop of linx writes only the slots
// of its own index, or merges per-chunk results in chunk order, so that results are the same to
// the bit for any number of threads (docs/performance.md, "Threads").
#pragma once

#include <cstddef>
#include <exception>

#include <omp.h>

namespace linx::parallel {

/// The thread count to use for a request: itself when positive, else one per hardware thread.
inline int resolveThreads(int requested) {
  return requested > 0 ? requested : omp_get_num_procs();
}

/// Runs f, keeping the first exception that any thread meets in `error`: an exception may not
/// leave a parallel region, so it is carried out of it and rethrown there.
template <class F>
void keepFirstError(std::exception_ptr& error, F&& f) {
  try {
    f();
  } catch (...) {
#pragma omp critical(linx_parallel_error)
    if (!error) error = std::current_exception();
  }
}

/// Calls body(i) for every i in [0, n): split over `threads` threads in static chunks when n is at
/// least `grain`, in order on the calling thread otherwise (a team costs microseconds to wake).
/// body(i) must write only what belongs to i. An exception thrown by body is rethrown here.
template <class Body>
void forEach(std::ptrdiff_t n, int threads, std::ptrdiff_t grain, Body&& body) {
  if (threads <= 1 || n < grain) {
    for (std::ptrdiff_t i = 0; i < n; ++i) body(i);
    return;
  }
  std::exception_ptr error;
#pragma omp parallel for num_threads(threads) schedule(static)
  for (std::ptrdiff_t i = 0; i < n; ++i) keepFirstError(error, [&] { body(i); });
  if (error) std::rethrow_exception(error);
}

/// Calls task(t) for every t in [0, tasks): coarse tasks of uneven cost (runs of broadphase
/// columns, chunks of pairs), handed to whichever thread is free. task(t) must write only what
/// belongs to t; the caller merges the tasks' results in task order.
template <class Task>
void forEachTask(std::ptrdiff_t tasks, int threads, Task&& task) {
  if (threads <= 1 || tasks < 2) {
    for (std::ptrdiff_t t = 0; t < tasks; ++t) task(t);
    return;
  }
  std::exception_ptr error;
#pragma omp parallel for num_threads(threads) schedule(dynamic, 1)
  for (std::ptrdiff_t t = 0; t < tasks; ++t) keepFirstError(error, [&] { task(t); });
  if (error) std::rethrow_exception(error);
}

/// Calls body(phase, i) for every i in [0, size(phase)) of each phase in [0, phases), the phases
/// one after the other (a graph colouring's colours): each phase's items split over `threads`
/// threads in static chunks, one team for all phases, a barrier between phases. A phase of fewer
/// than `grain` items runs on one thread. body(phase, i) must write only what belongs to i within
/// its phase, and size(phase) must not depend on what the bodies write. An exception thrown by
/// body is rethrown here.
template <class Size, class Body>
void forEachInPhases(int phases, int threads, std::ptrdiff_t grain, Size&& size, Body&& body) {
  bool wide = false;
  for (int p = 0; p < phases && threads > 1; ++p) wide = wide || size(p) >= grain;
  if (!wide) {
    for (int p = 0; p < phases; ++p)
      for (std::ptrdiff_t i = 0, n = size(p); i < n; ++i) body(p, i);
    return;
  }
  std::exception_ptr error;
#pragma omp parallel num_threads(threads)
  for (int p = 0; p < phases; ++p) {
    const std::ptrdiff_t n = size(p);
    if (n < grain) {
#pragma omp single
      for (std::ptrdiff_t i = 0; i < n; ++i) keepFirstError(error, [&] { body(p, i); });
    } else {
#pragma omp for schedule(static)
      for (std::ptrdiff_t i = 0; i < n; ++i) keepFirstError(error, [&] { body(p, i); });
    }
  }
  if (error) std::rethrow_exception(error);
}

}  // namespace linx::parallel
