#include "orchestrator/analysis/model_file.hpp"

#include "orchestrator/analysis/sobol_json.hpp"
#include "orchestrator/util/atomic_file.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/version.hpp"
#include "sobol/gp.hpp"
#include "sobol/rbf.hpp"
#include "sobol/rsm.hpp"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <cassert>
#include <cmath>
#include <system_error>

namespace demsa::analysis {

namespace {

using nlohmann::json;
using util::UserError;

json vector_json(const Eigen::VectorXd& v) {
  json a = json::array();
  for (Eigen::Index i = 0; i < v.size(); ++i) a.push_back(v(i));
  return a;
}

json matrix_json(const Eigen::MatrixXd& m) {
  json rows = json::array();
  for (Eigen::Index i = 0; i < m.rows(); ++i) rows.push_back(vector_json(m.row(i).transpose()));
  return rows;
}

/// Reads the fields of one model file; every failure names the file and the field ("gp.lengths[2]").
class Reader {
 public:
  explicit Reader(std::string file) : m_file(std::move(file)) {}

  [[noreturn]] void fail(const std::string& field, const std::string& message) const {
    throw UserError(m_file, 0, fmt::format("field '{}': {}", field, message));
  }

  const json& at(const json& object, const std::string& parent, const std::string& key) const {
    const std::string field = parent.empty() ? key : parent + "." + key;
    if (!object.is_object()) fail(parent, "is not a JSON object");
    const auto it = object.find(key);
    if (it == object.end()) fail(field, "missing");
    return *it;
  }

  double number(const json& v, const std::string& field) const {
    if (v.is_null()) fail(field, "null (not a finite number)");
    if (!v.is_number()) fail(field, fmt::format("{} is not a number", v.dump()));
    const double x = v.get<double>();
    if (!std::isfinite(x)) fail(field, fmt::format("{} is not a finite number", x));
    return x;
  }

  std::string text(const json& v, const std::string& field) const {
    if (!v.is_string()) fail(field, fmt::format("{} is not a string", v.dump().substr(0, 80)));
    return v.get<std::string>();
  }

  const json& array(const json& v, const std::string& field, std::size_t size_or_zero, std::size_t max) const {
    if (!v.is_array()) fail(field, "is not an array");
    if (size_or_zero != 0 && v.size() != size_or_zero)
      fail(field, fmt::format("{} entries, expected {}", v.size(), size_or_zero));
    if (v.size() > max) fail(field, fmt::format("{} entries, more than the {} read", v.size(), max));
    return v;
  }

  Eigen::VectorXd vector(const json& v, const std::string& field, std::size_t size_or_zero,
                         std::size_t max = k_max_model_rows) const {
    const json& a = array(v, field, size_or_zero, max);
    if (a.empty()) fail(field, "empty");
    Eigen::VectorXd out(static_cast<Eigen::Index>(a.size()));
    for (std::size_t i = 0; i < a.size(); ++i)
      out(static_cast<Eigen::Index>(i)) = number(a[i], fmt::format("{}[{}]", field, i));
    return out;
  }

  const std::string& file() const { return m_file; }

 private:
  std::string m_file;
};

}  // namespace

std::string model_file_name(const std::string& output, const std::string& kind) {
  return fmt::format("{}.{}.json", output, kind);
}

std::string model_to_json(const SavedModel& saved) {
  assert(saved.model && saved.model->fitted());
  const sobol::Metamodel& m = *saved.model;
  const Eigen::Index d = m.training_inputs().cols();
  assert(saved.inputs.size() == static_cast<std::size_t>(d) && saved.bounds.size() == saved.inputs.size());
  json inputs = json::array();
  for (std::size_t k = 0; k < saved.inputs.size(); ++k)
    inputs.push_back({{"name", saved.inputs[k]},
                      {"low", saved.bounds[k].low},
                      {"high", saved.bounds[k].high},
                      {"scale", sobol::to_string(saved.bounds[k].scale)}});
  json j = {{"format", k_model_format},
            {"format_version", k_model_format_version},
            {"demsa_version", k_version},
            {"kind", m.name()},
            {"output", saved.output},
            {"inputs", inputs},
            {"training",
             {{"unit_inputs", matrix_json(m.training_inputs())}, {"outputs", vector_json(m.training_outputs())}}}};
  if (const auto* rsm = dynamic_cast<const sobol::PolynomialRsm*>(&m)) {
    j["rsm"] = {{"degree", rsm->degree()},
                {"basis", "orthonormal shifted Legendre"},
                {"terms", rsm->terms()},
                {"coefficients", vector_json(rsm->coefficients())}};
  } else if (const auto* rbf = dynamic_cast<const sobol::RbfInterpolant*>(&m)) {
    j["rbf"] = {{"kernel", rbf->kind() == sobol::MetamodelKind::rbf_cubic ? "cubic" : "thin-plate"},
                {"tail", "linear"},
                {"weights", vector_json(rbf->weights())},
                {"tail_coefficients", vector_json(rbf->tail())}};
  } else if (const auto* gp = dynamic_cast<const sobol::GaussianProcess*>(&m)) {
    j["gp"] = {{"kernel", sobol::to_string(gp->options().kernel)},
               {"trend", sobol::to_string(gp->options().trend)},
               {"estimate_nugget", gp->options().nugget},
               {"lengths", vector_json(gp->lengths())},
               {"nugget", gp->nugget()},
               {"jitter", sobol::GaussianProcess::jitter()},
               {"process_variance", gp->process_variance()},
               {"trend_coefficients", vector_json(gp->trend_coefficients())},
               {"weights", vector_json(gp->weights())},
               {"log_likelihood", gp->log_likelihood()}};
  } else {
    assert(false && "model_to_json: a metamodel class without a file form");
  }
  j["quality"] = metamodel_summary_json(m.summary());
  return j.dump(1) + "\n";
}

void write_model_file(const std::filesystem::path& file, const SavedModel& model) {
  util::write_file_atomically(file, model_to_json(model));
}

namespace {

std::string read_bounded(const std::filesystem::path& file) {
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(file, ec);
  if (ec) throw UserError(file.string(), 0, fmt::format("cannot read the model file: {}", ec.message()));
  if (size > k_max_model_bytes)
    throw UserError(file.string(), 0,
                    fmt::format("{} bytes, more than the {} a model file may have", size, k_max_model_bytes));
  return util::read_file(file);
}

json parse_json(const std::string& text, const std::string& file) {
  try {
    return json::parse(text);
  } catch (const json::parse_error& e) {
    throw UserError(file, 0, fmt::format("not a JSON document: {}", e.what()));
  } catch (const json::out_of_range& e) {
    // A number beyond a double (1e999): nlohmann's 406, not a parse_error.
    throw UserError(file, 0, fmt::format("a number out of range: {}", e.what()));
  }
}

}  // namespace

sobol::MetamodelSummary read_model_quality(const std::filesystem::path& file) {
  const std::string name = file.string();
  const json j = parse_json(read_bounded(file), name);
  const Reader r(name);
  const json& q = r.at(j, "", "quality");
  try {
    return metamodel_summary_from_json(q);
  } catch (const json::exception& e) {
    r.fail("quality", e.what());
  }
}

std::string bad_name_reason(const std::string& name) {
  // The names become CSV headers (`demsa predict`) and file names: a safe character set, so that no cell starts with
  // = + - @ (a spreadsheet formula: OWASP, "CSV Injection") and none needs RFC 4180 quoting.
  if (name.empty()) return "empty";
  if (name.size() > k_max_name_length)
    return fmt::format("'{}...' is longer than {} characters", name.substr(0, 20), k_max_name_length);
  const auto letter = [](char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || c == '_'; };
  const auto digit = [](char c) { return c >= '0' && c <= '9'; };
  bool ok = letter(name.front());
  for (const char c : name) ok = ok && (letter(c) || digit(c) || c == '.' || c == '-');
  if (ok) return "";
  std::string shown;
  for (const char c : name.substr(0, 40))
    shown += (c >= 0x20 && c < 0x7f) ? std::string(1, c) : fmt::format("\\x{:02x}", static_cast<unsigned char>(c));
  return fmt::format("'{}' is not a name: a letter or '_' first, then letters, digits, '_', '.' or '-'", shown);
}

SavedModel parse_model_json(const std::string& text, const std::string& file) {
  const json j = parse_json(text, file);
  const Reader r(file);
  if (!j.is_object()) throw UserError(file, 0, "not a model file (the document is not a JSON object)");
  if (r.text(r.at(j, "", "format"), "format") != k_model_format)
    r.fail("format", fmt::format("'{}' is not '{}'", j.at("format").get<std::string>(), k_model_format));
  const json& version = r.at(j, "", "format_version");
  if (!version.is_number_integer() || version.get<long long>() != k_model_format_version)
    r.fail("format_version", fmt::format("{}: this demsa reads version {}", version.dump(), k_model_format_version));

  SavedModel saved;
  saved.demsa_version = r.text(r.at(j, "", "demsa_version"), "demsa_version");
  saved.output = r.text(r.at(j, "", "output"), "output");
  const std::string kind_name = r.text(r.at(j, "", "kind"), "kind");
  sobol::MetamodelKind kind{};
  try {
    kind = sobol::metamodel_kind_from_string(kind_name);
  } catch (const sobol::InputError& e) {
    r.fail("kind", e.what());
  }

  const json& inputs = r.array(r.at(j, "", "inputs"), "inputs", 0, k_max_model_inputs);
  if (inputs.empty()) r.fail("inputs", "empty");
  for (std::size_t k = 0; k < inputs.size(); ++k) {
    const std::string field = fmt::format("inputs[{}]", k);
    saved.inputs.push_back(r.text(r.at(inputs[k], field, "name"), field + ".name"));
    sobol::Bounds b;
    b.low = r.number(r.at(inputs[k], field, "low"), field + ".low");
    b.high = r.number(r.at(inputs[k], field, "high"), field + ".high");
    try {
      b.scale = sobol::scale_from_string(r.text(r.at(inputs[k], field, "scale"), field + ".scale"));
      sobol::validate_bounds({b}, {saved.inputs.back()});
    } catch (const sobol::InputError& e) {
      r.fail(field, e.what());
    }
    saved.bounds.push_back(b);
  }
  const std::size_t d = saved.inputs.size();
  for (std::size_t k = 0; k < d; ++k) {
    if (const std::string why = bad_name_reason(saved.inputs[k]); !why.empty())
      r.fail(fmt::format("inputs[{}].name", k), why);
    for (std::size_t i = 0; i < k; ++i)
      if (saved.inputs[i] == saved.inputs[k])
        r.fail(fmt::format("inputs[{}].name", k),
               fmt::format("'{}' is also inputs[{}]: names must be unique", saved.inputs[k], i));
  }
  if (const std::string why = bad_name_reason(saved.output); !why.empty()) r.fail("output", why);
  for (std::size_t k = 0; k < d; ++k)
    if (saved.inputs[k] == saved.output || saved.inputs[k] == saved.output + "_sd")
      r.fail("output", fmt::format("'{}' is also the name of inputs[{}] (a prediction's columns are the inputs, the "
                                   "output and OUTPUT_sd)",
                                   saved.output, k));

  const json& training = r.at(j, "", "training");
  const Eigen::VectorXd y = r.vector(r.at(training, "training", "outputs"), "training.outputs", 0);
  const std::size_t n = static_cast<std::size_t>(y.size());
  const json& rows = r.array(r.at(training, "training", "unit_inputs"), "training.unit_inputs", n, k_max_model_rows);
  Eigen::MatrixXd x(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(d));
  for (std::size_t i = 0; i < n; ++i)
    x.row(static_cast<Eigen::Index>(i)) =
        r.vector(rows[i], fmt::format("training.unit_inputs[{}]", i), d, k_max_model_inputs).transpose();

  try {
    if (kind == sobol::MetamodelKind::rsm1 || kind == sobol::MetamodelKind::rsm2 ||
        kind == sobol::MetamodelKind::rsm3) {
      const json& part = r.at(j, "", "rsm");
      const int degree = kind == sobol::MetamodelKind::rsm1 ? 1 : (kind == sobol::MetamodelKind::rsm2 ? 2 : 3);
      const double saved_degree = r.number(r.at(part, "rsm", "degree"), "rsm.degree");
      if (saved_degree != degree) r.fail("rsm.degree", fmt::format("{} for kind '{}'", saved_degree, kind_name));
      auto rsm = std::make_unique<sobol::PolynomialRsm>(degree);
      const Eigen::VectorXd c =
          r.vector(r.at(part, "rsm", "coefficients"), "rsm.coefficients",
                   static_cast<std::size_t>(sobol::PolynomialRsm::term_count(static_cast<int>(d), degree)),
                   std::size_t{1} << 24);
      rsm->restore(x, y, c);
      // The terms are recomputed from (d, degree); the file's list must be the same, in the same order.
      const json& terms = r.array(r.at(part, "rsm", "terms"), "rsm.terms", static_cast<std::size_t>(c.size()),
                                  static_cast<std::size_t>(c.size()));
      for (std::size_t t = 0; t < terms.size(); ++t) {
        const std::vector<int>& expected = rsm->terms()[t];
        if (!terms[t].is_array() || terms[t] != json(expected))
          r.fail(fmt::format("rsm.terms[{}]", t),
                 fmt::format("{} is not the multi-index {} of this basis", terms[t].dump(), json(expected).dump()));
      }
      saved.model = std::move(rsm);
    } else if (kind == sobol::MetamodelKind::rbf_cubic || kind == sobol::MetamodelKind::rbf_tps) {
      const json& part = r.at(j, "", "rbf");
      const std::string kernel = r.text(r.at(part, "rbf", "kernel"), "rbf.kernel");
      const std::string expected = kind == sobol::MetamodelKind::rbf_cubic ? "cubic" : "thin-plate";
      if (kernel != expected)
        r.fail("rbf.kernel", fmt::format("'{}' for kind '{}' (expected '{}')", kernel, kind_name, expected));
      const std::string tail = r.text(r.at(part, "rbf", "tail"), "rbf.tail");
      if (tail != "linear") r.fail("rbf.tail", fmt::format("'{}' (expected 'linear')", tail));
      auto rbf = std::make_unique<sobol::RbfInterpolant>(kind);
      rbf->restore(x, y, r.vector(r.at(part, "rbf", "weights"), "rbf.weights", n),
                   r.vector(r.at(part, "rbf", "tail_coefficients"), "rbf.tail_coefficients", d + 1));
      saved.model = std::move(rbf);
    } else {
      const json& part = r.at(j, "", "gp");
      sobol::GpOptions options;
      try {
        options.kernel = sobol::gp_kernel_from_string(r.text(r.at(part, "gp", "kernel"), "gp.kernel"));
      } catch (const sobol::InputError& e) {
        r.fail("gp.kernel", e.what());
      }
      try {
        options.trend = sobol::gp_trend_from_string(r.text(r.at(part, "gp", "trend"), "gp.trend"));
      } catch (const sobol::InputError& e) {
        r.fail("gp.trend", e.what());
      }
      const json& nugget_flag = r.at(part, "gp", "estimate_nugget");
      if (!nugget_flag.is_boolean())
        r.fail("gp.estimate_nugget", fmt::format("{} is not true or false", nugget_flag.dump()));
      options.nugget = nugget_flag.get<bool>();
      const double jitter = r.number(r.at(part, "gp", "jitter"), "gp.jitter");
      if (jitter != sobol::GaussianProcess::jitter())
        r.fail("gp.jitter", fmt::format("{}: this demsa's GP uses {}", jitter, sobol::GaussianProcess::jitter()));
      const std::size_t trend_terms = options.trend == sobol::GpTrend::constant ? 1 : d + 1;
      auto gp = std::make_unique<sobol::GaussianProcess>(options);
      gp->restore(x, y, r.vector(r.at(part, "gp", "lengths"), "gp.lengths", d),
                  r.number(r.at(part, "gp", "nugget"), "gp.nugget"),
                  r.vector(r.at(part, "gp", "trend_coefficients"), "gp.trend_coefficients", trend_terms),
                  r.vector(r.at(part, "gp", "weights"), "gp.weights", n),
                  r.number(r.at(part, "gp", "process_variance"), "gp.process_variance"));
      saved.model = std::move(gp);
    }
  } catch (const sobol::DataError& e) {
    throw UserError(file, 0, fmt::format("field 'training': {}", e.what()));
  } catch (const sobol::InputError& e) {
    throw UserError(file, 0, fmt::format("model '{}': {}", kind_name, e.what()));
  } catch (const sobol::NumericalError& e) {
    throw UserError(file, 0, fmt::format("field 'training': the model cannot be refitted to it: {}", e.what()));
  }
  return saved;
}

SavedModel read_model_file(const std::filesystem::path& file) {
  return parse_model_json(read_bounded(file), file.string());
}

}  // namespace demsa::analysis
