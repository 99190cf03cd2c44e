// The text syntax of measured values and observables (target_syntax.hpp).
#include "orchestrator/analysis/target_syntax.hpp"

#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/text.hpp"

#include <fmt/core.h>

#include <cmath>
#include <filesystem>

namespace demsa::analysis {

using util::trim;
using util::UserError;

namespace {

double number_of(const std::string& label, const std::string& whole, const std::string& text) {
  if (const std::optional<double> v = util::parse_number(text); v && std::isfinite(*v)) return *v;
  throw UserError(fmt::format("{} '{}': '{}' is not a number", label, whole, trim(text)));
}

/// "V1,V2,..." (a trailing comma ends the list).
std::vector<double> numbers_of(const std::string& label, const std::string& whole, const std::string& list) {
  std::vector<std::string> items = util::split(list, ',');
  if (!items.empty() && trim(items.back()).empty()) items.pop_back();
  if (items.empty()) throw UserError(fmt::format("{} '{}': no value", label, whole));
  std::vector<double> out;
  for (const std::string& item : items) out.push_back(number_of(label, whole, item));
  return out;
}

}  // namespace

QualifiedName parse_observable(const std::string& label, const std::string& text) {
  const auto colon = text.find(':');
  if (colon == std::string::npos) {
    if (trim(text).empty()) throw UserError(fmt::format("{} '{}': no observable named", label, text));
    return {"", trim(text)};
  }
  QualifiedName q{trim(text.substr(0, colon)), trim(text.substr(colon + 1))};
  if (q.study.empty() || q.name.empty())
    throw UserError(fmt::format("{} '{}': expected NAME or STUDY:NAME (STUDY: a study's [study] name)", label, text));
  return q;
}

std::vector<MeasuredTarget> parse_measured(const std::string& label, const std::string& text) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || trim(text.substr(0, eq)).empty())
    throw UserError(fmt::format("{} '{}': expected NAME=VALUE±ERROR", label, text));
  const std::string rest = text.substr(eq + 1);
  std::string values_text = rest, errors_text;
  for (const std::string sep : {"±", "+-"}) {
    const auto at = rest.find(sep);
    if (at != std::string::npos) {
      values_text = rest.substr(0, at);
      errors_text = rest.substr(at + sep.size());
      if (trim(errors_text).empty())
        throw UserError(fmt::format("{} '{}': no uncertainty after '{}'", label, text, sep));
      break;
    }
  }
  const std::vector<double> values = numbers_of(label, text, values_text);
  std::vector<double> errors(values.size(), 0.0);
  if (!errors_text.empty()) {
    const std::vector<double> e = numbers_of(label, text, errors_text);
    if (e.size() != 1 && e.size() != values.size())
      throw UserError(fmt::format("{} '{}': {} uncertainties for {} values (give one or one per value)", label, text,
                                  e.size(), values.size()));
    for (size_t i = 0; i < values.size(); ++i) {
      errors[i] = e.size() == 1 ? e[0] : e[i];
      // An explicit ± 0 claims an exact measurement: the likelihood then rests on the metamodel's error alone, which
      // is near 0 where the metamodel interpolates, and the posterior collapses onto whatever point it picks.
      if (!(errors[i] > 0))
        throw UserError(
            fmt::format("{} '{}': uncertainty {:g} must be > 0 (the measurement's standard deviation; "
                        "without ± the value is matched by the optimize method)",
                        label, text, errors[i]));
    }
  }
  const QualifiedName name = parse_observable(label, text.substr(0, eq));
  std::vector<MeasuredTarget> out;
  for (size_t i = 0; i < values.size(); ++i)
    out.push_back(
        {name.study, values.size() == 1 ? name.name : curve_point_name(name.name, i + 1), values[i], errors[i]});
  return out;
}

std::vector<MeasuredTarget> read_target_file(const std::string& label, const std::string& text) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || trim(text.substr(0, eq)).empty() || trim(text.substr(eq + 1)).empty())
    throw UserError(fmt::format("{} '{}': expected NAME=FILE.csv", label, text));
  const QualifiedName name = parse_observable(label, text.substr(0, eq));
  const std::filesystem::path file = trim(text.substr(eq + 1));
  if (!std::filesystem::exists(file))
    throw UserError(fmt::format("{} '{}': {} does not exist", label, text, file.string()));
  return read_measured_curve(name.study, name.name, file);
}

std::pair<std::string, double> parse_weight(const std::string& label, const std::string& text) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || trim(text.substr(0, eq)).empty())
    throw UserError(fmt::format("{} '{}': expected NAME=W", label, text));
  const std::vector<double> w = numbers_of(label, text, text.substr(eq + 1));
  if (w.size() != 1 || w[0] < 0) throw UserError(fmt::format("{} '{}': one value >= 0 expected", label, text));
  return {parse_observable(label, text.substr(0, eq)).label(), w[0]};
}

ObservableSd parse_observable_sd(const std::string& label, const std::string& text) {
  const auto eq = text.rfind('=');
  if (eq == std::string::npos) throw UserError(fmt::format("{} '{}': expected NAME=SD or STUDY:NAME=SD", label, text));
  const std::optional<double> v = util::parse_number(trim(text.substr(eq + 1)));
  if (!v)
    throw UserError(
        fmt::format("{} '{}': '{}' must be a number > 0 (the observable's standard deviation, in the "
                    "units demsa stores it: SI, angles in degrees)",
                    label, text, trim(text.substr(eq + 1))));
  return {parse_observable(label, text.substr(0, eq)), *v};
}

}  // namespace demsa::analysis
