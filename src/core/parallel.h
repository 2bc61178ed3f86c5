// The passes over points and voxels split across threads so that the result does not depend
// on the number of threads: the indices are cut into contiguous shares, each share is worked
// on by one thread and touches only what it owns, and whatever the shares add up is combined
// afterwards in share order. The threads are worker_pool.h's: helpers that sleep when idle
// and a caller that runs every share no helper has started, so more threads never cost a
// loaded machine more than their wake-ups. Private to the core library.
#pragma once

#include <algorithm>
#include <cstddef>
#include <thread>

#include "worker_pool.h"

namespace hope {
namespace parallel {

// The number of cores, at least 1.
inline int cores() { return std::max(1, static_cast<int>(std::thread::hardware_concurrency())); }

// The number of threads for Params::threads: 0 means every core.
inline int resolve(int requested) { return requested > 0 ? requested : cores(); }

// Pool helpers for `shares` shares: one share is the caller's, and more threads than cores
// would only take turns (a request for more shares still gets them, run by fewer threads).
inline int helpersFor(int shares) { return std::min(shares, cores()) - 1; }

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
  const auto share = static_cast<std::size_t>(shares);
  WorkerPool::shared().run(share, helpersFor(shares), [&](std::size_t s) {
    body(static_cast<int>(s), n * s / share, n * (s + 1) / share);
  });
  return shares;
}

// Calls body(i) for each i in [0, n) on up to `threads` threads, items handed out one at a time
// (for work whose cost varies from item to item, like planes of different sizes).
template <class Body>
void forEach(std::size_t n, int threads, Body body) {
  if (threads <= 1 || n <= 1) {
    for (std::size_t i = 0; i < n; ++i) body(i);
    return;
  }
  WorkerPool::shared().run(n, helpersFor(threads), [&](std::size_t i) { body(i); });
}

}  // namespace parallel
}  // namespace hope
