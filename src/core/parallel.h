// The passes over points and voxels split across threads (OpenMP) so that the result does not
// depend on the number of threads: each thread takes a contiguous share of the indices, works
// only on what it owns, and whatever the shares add up is combined afterwards in share order.
// Private to the core library.
#pragma once

#include <algorithm>
#include <cstddef>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace hope {
namespace parallel {

// The number of threads for Params::threads: 0 means every core.
inline int resolve(int requested) {
#ifdef _OPENMP
  return requested > 0 ? requested : std::max(1, omp_get_num_procs());
#else
  (void)requested;
  return 1;
#endif
}

// Calls body(share, begin, end) for `shares` contiguous shares of [0, n), in parallel on up
// to `threads` threads. Below `min_per_share` items per share fewer shares are used (down to
// one): starting threads costs microseconds. Returns the number of shares.
template <class Body>
int forShares(std::size_t n, int threads, std::size_t min_per_share, Body body) {
  const std::size_t useful = std::max<std::size_t>(1, n / std::max<std::size_t>(1, min_per_share));
  const int shares = static_cast<int>(std::min<std::size_t>(std::max(1, threads), useful));
  if (shares == 1) {
    body(0, std::size_t{0}, n);
    return 1;
  }
#ifdef _OPENMP
#pragma omp parallel for num_threads(shares) schedule(static, 1)
#endif
  for (int s = 0; s < shares; ++s) {
    body(s, n * static_cast<std::size_t>(s) / static_cast<std::size_t>(shares),
         n * static_cast<std::size_t>(s + 1) / static_cast<std::size_t>(shares));
  }
  return shares;
}

// Calls body(i) for each i in [0, n) on up to `threads` threads, items handed out in small
// chunks (for work whose cost varies from item to item, like planes of different sizes).
template <class Body>
void forEach(std::size_t n, int threads, Body body) {
  if (threads <= 1 || n <= 1) {
    for (std::size_t i = 0; i < n; ++i) body(i);
    return;
  }
#ifdef _OPENMP
#pragma omp parallel for num_threads(threads) schedule(dynamic, 1)
#endif
  for (std::ptrdiff_t i = 0; i < static_cast<std::ptrdiff_t>(n); ++i) {
    body(static_cast<std::size_t>(i));
  }
}

}  // namespace parallel
}  // namespace hope
