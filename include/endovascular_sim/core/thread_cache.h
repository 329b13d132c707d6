// Per-thread caches of the core's hot paths (scratch that a step reuses
// instead of allocating), each on the heap behind one pointer.
#pragma once

#include <memory>

namespace evsim {

/// This thread's instance of T: default-constructed at its first use,
/// destroyed with the thread. Only the pointer is thread_local: the
/// libraries are built with -ftls-model=initial-exec (one load an access)
/// and are also loaded by dlopen (the Python module), where glibc has room
/// for a few hundred bytes of such variables in all. `Tag` tells apart two
/// caches of one type.
template <typename T, typename Tag = T>
T& threadCache() {
  thread_local std::unique_ptr<T> instance;
  if (!instance) instance = std::make_unique<T>();
  return *instance;
}

}  // namespace evsim
