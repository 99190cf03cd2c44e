#pragma once
// Errors a caller's input can cause in demsa::sobol (bad data, bad options). The message names the source
// (file, row, column, value) when there is one; programming errors are assertions instead.
#include <stdexcept>
#include <string>

namespace demsa::sobol {

class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

/// A numerical failure that the input caused (singular system, no convergence): the caller decides.
class NumericalError : public std::runtime_error {
 public:
  explicit NumericalError(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace demsa::sobol
