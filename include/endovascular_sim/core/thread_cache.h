// Per-thread caches of the core's hot paths, each on the heap behind one
// pointer: storage a call reuses instead of allocating (the Delassus
// update's, the status method's factor buffer), and caches of a model's
// geometry keyed by what they were computed from (the moved vessel
// segments by field and motion, the field's Hessian bounds by field and
// cell, the interior balls' deformation rate by motion), so that what they
// hold is right for any simulation a thread steps. What a simulation keeps
// for its own next steps (device-pair candidates, the loops' rows, the
// sub-steps' states) lives in its SimData instead (contact/contact_workspace.h).
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
