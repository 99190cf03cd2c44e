// The report document rendered: Markdown (figures as files beside it) and self-contained HTML (figures inlined),
// and the text helpers of both (report.hpp). What the study report says is report.cpp's.
#include "orchestrator/report/report.hpp"

#include "orchestrator/report/posterior_plots.hpp"

#include "orchestrator/analysis/analysis_json.hpp"
#include "orchestrator/analysis/calibration.hpp"
#include "orchestrator/analysis/calibration_posterior.hpp"
#include "orchestrator/analysis/experiment_plan.hpp"
#include "orchestrator/analysis/fit.hpp"
#include "orchestrator/analysis/study_analysis.hpp"
#include "orchestrator/analysis/training_data.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/config.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/study/observables.hpp"
#include "orchestrator/study/parameters.hpp"
#include "orchestrator/study/store.hpp"
#include "orchestrator/util/atomic_file.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/text.hpp"
#include "sobol/metamodel.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <exception>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <string_view>
#include <type_traits>
#include <variant>

namespace demsa::report {

using namespace demsa::util;
using namespace demsa::study;
using namespace demsa::analysis;
namespace fs = std::filesystem;

std::string base64_encode(const std::string& bytes) {
  static constexpr char k_alphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned v = static_cast<unsigned char>(bytes[i]) << 16 | static_cast<unsigned char>(bytes[i + 1]) << 8 |
                       static_cast<unsigned char>(bytes[i + 2]);
    out += k_alphabet[(v >> 18) & 63];
    out += k_alphabet[(v >> 12) & 63];
    out += k_alphabet[(v >> 6) & 63];
    out += k_alphabet[v & 63];
  }
  if (i + 1 == bytes.size()) {
    const unsigned v = static_cast<unsigned char>(bytes[i]) << 16;
    out += k_alphabet[(v >> 18) & 63];
    out += k_alphabet[(v >> 12) & 63];
    out += "==";
  } else if (i + 2 == bytes.size()) {
    const unsigned v = static_cast<unsigned char>(bytes[i]) << 16 | static_cast<unsigned char>(bytes[i + 1]) << 8;
    out += k_alphabet[(v >> 18) & 63];
    out += k_alphabet[(v >> 12) & 63];
    out += k_alphabet[(v >> 6) & 63];
    out += '=';
  }
  return out;
}

namespace {

std::string html_escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

/// Inline Markdown `code` (CommonMark code spans: a run of n backticks up to the next run of exactly n, one space
/// stripped from each end when both are spaces) and *emphasis* as HTML (after escaping).
std::string html_inline(const std::string& text) {
  const std::string escaped = html_escape(text);
  const auto run_at = [&](std::size_t i) {
    std::size_t n = 0;
    while (i + n < escaped.size() && escaped[i + n] == '`') ++n;
    return n;
  };
  std::string out;
  bool em = false;
  for (std::size_t i = 0; i < escaped.size();) {
    const char c = escaped[i];
    if (c == '`') {
      const std::size_t n = run_at(i);
      std::size_t close = i + n;  // the start of a run of exactly n backticks (runs are skipped whole)
      while (close < escaped.size() && !(escaped[close] == '`' && run_at(close) == n))
        close += escaped[close] == '`' ? run_at(close) : 1;
      if (close >= escaped.size()) {  // no closing run: the backticks are text
        out.append(n, '`');
        i += n;
        continue;
      }
      std::string code = escaped.substr(i + n, close - i - n);
      if (code.size() >= 2 && code.front() == ' ' && code.back() == ' ' &&
          code.find_first_not_of(' ') != std::string::npos)
        code = code.substr(1, code.size() - 2);
      out += "<code>" + code + "</code>";
      i = close + n;
    } else if (c == '*') {
      out += em ? "</em>" : "<em>";
      em = !em;
      ++i;
    } else {
      out += c;
      ++i;
    }
  }
  if (em) out += "</em>";
  return out;
}

std::string md_cell(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '|') out += "\\";
    out += c;
  }
  return out;
}

/// Plain text as Markdown that shows it as it is: CommonMark's backslash escapes for the punctuation that could start
/// emphasis, code, a link, raw HTML or an entity, and no line break (a study name is the user's text).
std::string md_text(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '\n' || c == '\r' || c == '\t') c = ' ';
    if (std::string_view("\\`*_{}[]<>()#+-!|&~").find(c) != std::string_view::npos) out += '\\';
    out += c;
  }
  return out;
}

std::string read_binary(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw util::IoError(fmt::format("{}: cannot read: {}", path.string(), std::strerror(errno)));
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

std::string code_span(const std::string& text) {
  std::string content;
  std::size_t longest = 0, run = 0;
  for (char c : text) {
    if (c == '\n' || c == '\r' || c == '\t') c = ' ';
    run = c == '`' ? run + 1 : 0;
    longest = std::max(longest, run);
    content += c;
  }
  const std::string fence(longest + 1, '`');
  if (!content.empty() &&
      (content.front() == '`' || content.back() == '`' || (content.front() == ' ' && content.back() == ' ')))
    content = " " + content + " ";
  return fence + content + fence;
}

std::string render_markdown(const ReportDocument& document, const fs::path& folder) {
  std::string md = fmt::format("# {}\n", md_text(document.title));
  for (const ReportSection& s : document.sections) {
    md += fmt::format("\n{} {}\n", std::string(static_cast<size_t>(std::clamp(s.level, 2, 4)), '#'), s.heading);
    for (const std::string& p : s.paragraphs) md += fmt::format("\n{}\n", p);
    for (const ReportTable& t : s.tables) {
      if (!t.caption.empty()) md += fmt::format("\n*{}*\n", t.caption);
      md += "\n|";
      for (const std::string& h : t.header) md += fmt::format(" {} |", md_cell(h));
      md += "\n|";
      for (size_t i = 0; i < t.header.size(); ++i) md += i == 0 ? " :--- |" : " ---: |";
      md += "\n";
      for (const std::vector<std::string>& row : t.rows) {
        md += "|";
        for (const std::string& c : row) md += fmt::format(" {} |", md_cell(c));
        md += "\n";
      }
    }
    for (const ReportFigure& f : s.figures) {
      const std::string png = fs::relative(f.files.png, folder).generic_string();
      if (f.files.script.empty()) {  // a picture, not a plot
        md += fmt::format("\n![{}]({})\n\n*{}*\n", f.caption, png, f.caption);
        continue;
      }
      const std::string svg = fs::relative(f.files.svg, folder).generic_string();
      const std::string gp = fs::relative(f.files.script, folder).generic_string();
      md += fmt::format("\n![{}]({})\n\n*{}* ([SVG]({}), [gnuplot script]({}))\n", f.caption, png, f.caption, svg, gp);
    }
  }
  return md;
}

std::string render_html(const ReportDocument& document) {
  std::string html =
      "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>" + html_escape(document.title) +
      "</title>\n<style>\n"
      "body { font-family: 'DejaVu Sans', Helvetica, Arial, sans-serif; max-width: 1100px; margin: 2em auto; "
      "padding: 0 1em; color: #222; line-height: 1.45; }\n"
      "table { border-collapse: collapse; margin: 0.6em 0 1.2em; font-size: 0.92em; }\n"
      "th, td { border: 1px solid #bbb; padding: 0.25em 0.6em; text-align: right; }\n"
      "th:first-child, td:first-child { text-align: left; }\n"
      "th { background: #eef1f6; }\n caption { caption-side: top; font-style: italic; text-align: left; "
      "padding-bottom: 0.3em; }\n"
      "figure { margin: 1.2em 0; } figure img { max-width: 100%; border: 1px solid #ddd; }\n"
      "figcaption { font-style: italic; }\n code { background: #f3f3f3; padding: 0 0.2em; }\n"
      "</style>\n</head>\n<body>\n";
  html += "<h1>" + html_escape(document.title) + "</h1>\n";
  for (const ReportSection& s : document.sections) {
    const int level = std::clamp(s.level, 2, 4);
    html += fmt::format("<h{0}>{1}</h{0}>\n", level, html_inline(s.heading));  // "Observable `angle`" as code
    for (const std::string& p : s.paragraphs) html += "<p>" + html_inline(p) + "</p>\n";
    for (const ReportTable& t : s.tables) {
      html += "<table>\n";
      if (!t.caption.empty()) html += "<caption>" + html_inline(t.caption) + "</caption>\n";
      html += "<tr>";
      for (const std::string& h : t.header) html += "<th>" + html_escape(h) + "</th>";
      html += "</tr>\n";
      for (const std::vector<std::string>& row : t.rows) {
        html += "<tr>";
        for (const std::string& c : row) html += "<td>" + html_escape(c) + "</td>";
        html += "</tr>\n";
      }
      html += "</table>\n";
    }
    for (const ReportFigure& f : s.figures) {
      html += "<figure><img alt=\"" + html_escape(f.caption) + "\" src=\"data:image/png;base64," +
              base64_encode(read_binary(f.files.png)) + "\">\n<figcaption>" + html_escape(f.caption) +
              "</figcaption></figure>\n";
    }
  }
  html += "</body>\n</html>\n";
  return html;
}

}  // namespace demsa::report
