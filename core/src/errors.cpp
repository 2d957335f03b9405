#include "sphforge/errors.hpp"

namespace sphforge {

// Out-of-line key functions: the vtables and type_info of the error types are emitted here, in
// libsphforge_core, and nowhere else (errors.hpp explains why).
InputError::~InputError() = default;
InstabilityError::~InstabilityError() = default;

}  // namespace sphforge
