// failure.h: how the shim's C++ code fails. A Failure is thrown inside the shim and turned into
// a status and message at the C edge (openmesh_shim.cpp, guarded()); it never leaves the shim.
#pragma once

#include <string>

#include "openmesh_shim.h"

namespace omsys {

struct Failure {
  OmsysStatus status;
  std::string message;
};

[[noreturn]] inline void fail(OmsysStatus status, std::string message) { throw Failure{status, std::move(message)}; }

}  // namespace omsys
