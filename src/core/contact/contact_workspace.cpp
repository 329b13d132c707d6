// A simulation's contact workspace (contact/contact_workspace.h).
#include "endovascular_sim/contact/contact_workspace.h"

#include "contact_workspace_kept.h"

namespace evsim {

ContactWorkspace::ContactWorkspace() = default;
ContactWorkspace::~ContactWorkspace() = default;
ContactWorkspace::ContactWorkspace(const ContactWorkspace& other)
    : kept_(other.kept_ ? std::make_unique<Kept>(*other.kept_) : nullptr) {}
ContactWorkspace& ContactWorkspace::operator=(const ContactWorkspace& other) {
  if (this != &other) kept_ = other.kept_ ? std::make_unique<Kept>(*other.kept_) : nullptr;
  return *this;
}
ContactWorkspace::ContactWorkspace(ContactWorkspace&&) noexcept = default;
ContactWorkspace& ContactWorkspace::operator=(ContactWorkspace&&) noexcept = default;

ContactWorkspace::Kept& ContactWorkspace::kept() {
  if (!kept_) kept_ = std::make_unique<Kept>();
  return *kept_;
}

}  // namespace evsim
