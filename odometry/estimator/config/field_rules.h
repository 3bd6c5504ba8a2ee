// The checks the estimator's option structs share: an error "<section>.<field>: must be <rule>, got <value>"
// and the finite-and-positive test.
#pragma once

#include <cmath>
#include <sstream>

#include "odometry/types/status.h"

namespace uf::estimator {

template <typename T>
Status FieldMustBe(const char* section, const char* field, const char* rule, T value) {
  std::ostringstream message;
  message << section << "." << field << ": must be " << rule << ", got " << value;
  return Status::Error(message.str());
}

inline bool Positive(double v) { return std::isfinite(v) && v > 0; }

}  // namespace uf::estimator
