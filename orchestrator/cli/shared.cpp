#include "orchestrator/cli/shared.hpp"

#include "orchestrator/util/signals.hpp"
#include "orchestrator/util/text.hpp"

#include <fmt/core.h>

#include <cmath>
#include <cstdlib>
#include <functional>

namespace demsa::cli {

namespace {

/// A validator of a finite number for which `rule` holds; `text` is the rule in words ("> 0").
CLI::Validator number_check(std::function<bool(double)> rule, const std::string& text) {
  return CLI::Validator(
      [rule, text](std::string& input) -> std::string {
        const std::string t = util::trim(input);
        char* end = nullptr;
        const double value = std::strtod(t.c_str(), &end);
        if (t.empty() || end != t.c_str() + t.size()) return fmt::format("'{}' is not a number", input);
        if (!std::isfinite(value))
          return fmt::format("{}: must be a finite number{}", input, text.empty() ? "" : " " + text);
        if (!rule(value)) return fmt::format("{}: must be {}", input, text);
        return {};
      },
      text.empty() ? "NUMBER" : text, text);
}

}  // namespace

int interrupted_status() {
  const int sig = util::StopFlag::signal_number();
  return sig > 0 ? util::k_exit_signal_base + sig : util::k_exit_check_failed;
}

CLI::Validator finite_number() {
  return number_check([](double) { return true; }, "");
}
CLI::Validator positive_number() {
  return number_check([](double v) { return v > 0; }, "> 0");
}
CLI::Validator non_negative_number() {
  return number_check([](double v) { return v >= 0; }, ">= 0");
}
CLI::Validator number_in(double low, double high) {
  return number_check([low, high](double v) { return v >= low && v <= high; }, fmt::format("in [{}, {}]", low, high));
}

CLI::Validator integer_in(long low, long high) {
  const std::string text = fmt::format("a whole number in [{}, {}]", low, high);
  return number_check(
      [low, high](double v) {
        return v == std::floor(v) && v >= static_cast<double>(low) && v <= static_cast<double>(high);
      },
      text);
}

}  // namespace demsa::cli
