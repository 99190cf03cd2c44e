#pragma once
// `demsa report DIR`: the report of a study as DIR/report/report.md and a self-contained DIR/report/report.html
// (images inlined as base64 data URIs), with every plot as PNG and SVG and its gnuplot script next to it.
//
// Contents (the paper's Tables 4–7 and Figs. 4, 5, 6b, and what a DEM engineer needs around them):
//   - study summary: experiment, varied parameters and ranges, samples done / failed / pending, failed samples by
//     failure class, CPU hours of all attempts;
//   - per observable: metamodel quality (R², adjusted R², leave-one-out Q², RMSE_LOO); S1 per parameter and the
//     residual 1 − ΣS1 per metamodel (the paper's table layout), ST, and the S2 matrix, each with its confidence
//     interval; Sobol' bars with interval whiskers per metamodel; leave-one-out predicted against simulated per
//     metamodel; the response against each parameter;
//   - one sample seen closely: the pile from the side with its boundary particles and fitted lines (Fig. 4), or the
//     oedometer's settlement–stress curve against the measured settlements (Fig. 5) and its plate iteration
//     history (Fig. 6b);
//   - the calibration (DIR/analysis/calibration.json, from `demsa calibrate`), when there is one.
//
// Inputs: DIR/study.toml, DIR/study.db, DIR/analysis/analysis.json (made by `demsa analyze` when missing), the
// case folder of the sample shown, DIR/analysis/calibration.json.
//
// The document model below (ReportDocument) is plain data: the study-specific part builds it, render_markdown()
// and render_html() only lay it out.
#include "orchestrator/report/plot.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace demsa::report {

using ReportTable = experiments::CaseTable;

struct ReportFigure {
  std::string caption;
  PlotFiles files;
};

struct ReportSection {
  std::string heading;
  int level = 2;                        ///< 2: "##", 3: "###"
  std::vector<std::string> paragraphs;  ///< plain text (Markdown inline syntax allowed: `code`, *emphasis*)
  std::vector<ReportTable> tables;
  std::vector<ReportFigure> figures;
};

struct ReportDocument {
  std::string title;
  std::vector<ReportSection> sections;
};

/// `text` (a user's: a study name) as one Markdown code span that shows it as it is, whatever backticks it holds
/// (CommonMark: a fence of more backticks than its longest run, padded by a space where the text starts or ends with
/// one) and with its line breaks and tabs as spaces (a blank line would end the paragraph). render_html reads it back.
std::string code_span(const std::string& text);

/// Markdown with images referenced relative to `folder` (where report.md is written), each linked to its SVG.
std::string render_markdown(const ReportDocument& document, const std::filesystem::path& folder);

/// One HTML page with inline CSS and every PNG inlined as a base64 data URI (no other file needed to view it).
/// Throws std::runtime_error when an image cannot be read.
std::string render_html(const ReportDocument& document);

/// RFC 4648 base64 of `bytes` (with padding).
std::string base64_encode(const std::string& bytes);

/// A lower bound below 0, shown clipped at 0.
inline constexpr const char* k_clipped_low = "0.000*";

/// "0.530 [0.512, 0.551]", three decimals throughout; the interval is left out when it is NaN or collapsed onto the
/// value; a lower bound below 0 is shown as k_clipped_low.
std::string format_interval(double value, double low, double high);

struct ReportOptions {
  std::filesystem::path dir;  ///< study folder
  std::filesystem::path out;  ///< output folder; empty: DIR/report
  PlotOptions plot;           ///< gnuplot and image size
  /// Sample shown in the pile / oedometer figures; -1: the done sample whose observable is closest to the target
  /// (pile: the target angle; oedometer: smallest E_0, else the median settlement). >= -1.
  int sample = -1;
  bool html = true;  ///< also write report.html
  /// A laboratory file of the study's setup (a drum's photograph; empty: none): the case section shows the case
  /// superimposed on it and their mismatch area (Experiment::compare_with_lab_file).
  std::filesystem::path lab_file;
  /// Throws util::UserError naming the field, value and rule.
  void validate() const;
};

struct ReportSummary {
  std::filesystem::path out_dir;
  std::filesystem::path markdown;             ///< report.md
  std::filesystem::path html;                 ///< report.html (empty when not written)
  std::vector<std::filesystem::path> images;  ///< every PNG written
  std::vector<std::string> notes;             ///< what could not be drawn, and why
  int sample_shown = -1;                      ///< the sample of the pile / oedometer figures (-1: none)
};

/// Writes the report of a study. Throws util::UserError when DIR is not a study or has fewer than two done samples.
ReportSummary write_study_report(const ReportOptions& options);

/// {"dir", "markdown", "html", "sample_shown", "notes", "images"}: what was written, as `demsa report --json` prints
/// it.
nlohmann::json report_summary_json(const ReportSummary& summary);

/// What was written in words: "report: FILE" for report.md and report.html, the plots' count and folder, a line per
/// note.
std::string report_summary_text(const ReportSummary& summary);

}  // namespace demsa::report
