// What the contact solver keeps for one simulation from loop to loop and
// from step to step: the device-pair candidates (valid for several steps
// while the points move less than their skin) and the storage of the
// loop's rows. It lives in the simulation's data (sim/simulation.h,
// SimData::contact), not in the thread that steps it, so any thread may
// step any simulation and find what that simulation kept.
#pragma once

#include <memory>

namespace evsim {

class ContactWorkspace {
 public:
  struct Kept;  // src/core/contact/contact_workspace_kept.h

  ContactWorkspace();
  ~ContactWorkspace();
  /// A copy holds what the original holds, so a copied simulation steps to
  /// the original's states to the last bit (a fresh workspace finds the same
  /// pairs, candidates being checked before each use, in another order: the
  /// same answer to round-off).
  ContactWorkspace(const ContactWorkspace&);
  ContactWorkspace& operator=(const ContactWorkspace&);
  ContactWorkspace(ContactWorkspace&&) noexcept;
  ContactWorkspace& operator=(ContactWorkspace&&) noexcept;

  /// Created at the first use.
  Kept& kept();

 private:
  std::unique_ptr<Kept> kept_;
};

}  // namespace evsim
