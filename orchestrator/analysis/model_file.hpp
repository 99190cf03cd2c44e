#pragma once
// A fitted metamodel as a self-contained JSON file: what `demsa predict` reads and what the study analysis
// (DIR/analysis/models/<observable>.<metamodel>.json) and `demsa sensitivity --save-model` write.
//
//   {"format": "demsa-metamodel", "format_version": 1, "demsa_version": "...",
//    "kind": "rsm2" | "rsm1" | "rsm3" | "rbf-cubic" | "rbf-tps" | "gp",
//    "output": NAME,
//    "inputs": [{"name", "low", "high", "scale": "uniform" | "log"}, ...],   u = (x - low)/(high - low), or
//                                                                              log(x/low)/log(high/low) for "log"
//    "training": {"unit_inputs": [[u_1..u_d], ...] (n rows), "outputs": [y, ...] (n)},
//    "rsm": {"degree", "basis": "orthonormal shifted Legendre", "terms": [[a_1..a_d], ...],
//            "coefficients": [...]}                      ŷ(u) = Σ_t c_t Π_k L_{a_tk}(u_k), L_a = √(2a+1) P_a(2u - 1)
//    "rbf": {"kernel": "cubic" (φ = r³) | "thin-plate" (φ = r² log r²), "tail": "linear",
//            "weights": [w_i] (n), "tail_coefficients": [c_0, c_1..c_d]}
//                                                        ŷ(u) = Σ_i w_i φ(|u - u_i|) + c_0 + Σ_k c_k u_k
//    "gp": {"kernel": "squared-exponential" | "matern52", "trend": "constant" | "linear", "estimate_nugget",
//           "lengths": [θ_k] (d), "nugget", "jitter", "process_variance", "trend_coefficients": [β], "weights": [α]
//           (n), "log_likelihood"}
//                                                        ŷ(u) = f(u)ᵀβ + Σ_i α_i k((u - u_i)/θ), f = (1[, u_1..u_d]);
//                                                        sd(u)² = σ² (1 + τ - r(u)ᵀ (R + (τ + jitter) I)⁻¹ r(u))
//    "quality": the metamodel summary of sobol_json.hpp (R², Q², ...)}
//
// The coefficients are the model: reading a file predicts with them bit for bit. The training data serve the rest
// (leave-one-out, refits of a design bootstrap, the GP's Cholesky factor): reading refits the model to them with
// the saved hyperparameters, so a file holds no more than n ≤ k_max_model_rows training points.
#include "sobol/metamodel.hpp"
#include "sobol/scaling.hpp"

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace demsa::analysis {

inline constexpr const char* k_model_format = "demsa-metamodel";
inline constexpr int k_model_format_version = 1;
inline constexpr std::uintmax_t k_max_model_bytes = std::uintmax_t{256} << 20;  ///< largest model file read
inline constexpr int k_max_model_rows = 20000;                                  ///< most training points read
inline constexpr int k_max_model_inputs = 1000;                                 ///< most inputs read
inline constexpr std::size_t k_max_name_length = 64;                            ///< longest input or output name

/// Why `name` cannot name a model's input or output ("" when it can): it must start with a letter or '_' and hold
/// only letters, digits, '_', '.' and '-' (at most k_max_name_length), so that it is a CSV header needing no
/// quoting and never a formula (=, +, -, @ first). parse_model_json refuses such names, repeated input names and an
/// output named like an input.
std::string bad_name_reason(const std::string& name);

/// A metamodel with the names and ranges of its inputs, in physical units.
struct SavedModel {
  std::unique_ptr<sobol::Metamodel> model;  ///< fitted
  std::vector<std::string> inputs;          ///< input names, in the model's order
  std::vector<sobol::Bounds> bounds;        ///< per input: the unit-cube mapping
  std::string output;                       ///< the modelled output (observable, response column)
  std::string demsa_version;                ///< of the demsa that wrote the file ("" before writing)
};

/// The JSON text of a model (format above). model.model must be fitted; inputs and bounds as many as its inputs.
std::string model_to_json(const SavedModel& model);

/// Writes model_to_json atomically (util::write_file_atomically).
void write_model_file(const std::filesystem::path& file, const SavedModel& model);

/// Reads a model file. Throws util::UserError naming the file and the field for anything wrong: not JSON, another
/// format or kind, a missing or mistyped field, a size that disagrees with the others, a non-finite number, a file or
/// training set beyond the limits above, or training data the model cannot be refitted to.
SavedModel read_model_file(const std::filesystem::path& file);
/// read_model_file on text; `file` names it in messages.
SavedModel parse_model_json(const std::string& text, const std::string& file);

/// The quality (Q², ...) recorded in a model file, without refitting it (for choosing among files).
sobol::MetamodelSummary read_model_quality(const std::filesystem::path& file);

/// "<output>.<kind>.json": the name of a model file in a folder of models (analysis/models/, --save-model DIR).
std::string model_file_name(const std::string& output, const std::string& kind);

}  // namespace demsa::analysis
