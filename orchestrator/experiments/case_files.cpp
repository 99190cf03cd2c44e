#include "orchestrator/experiments/case_files.hpp"

#include "orchestrator/experiments/embedded_templates.hpp"
#include "orchestrator/util/atomic_file.hpp"
#include "orchestrator/util/signals.hpp"

#include <fmt/core.h>

#include <cassert>
#include <fstream>
#include <iterator>

namespace demsa::experiments {

void Params::comment(const std::string& text) { m_text += "\n# " + text + "\n"; }

void Params::number(const std::string& name, double value, const std::string& note) {
  m_text += fmt::format("variable {:<20} equal {:<24} # {}\n", name, fmt::format("{}", value), note);
}

void Params::integer(const std::string& name, long value, const std::string& note) {
  m_text += fmt::format("variable {:<20} equal {:<24} # {}\n", name, value, note);
}

void Params::word(const std::string& name, const std::string& value, const std::string& note) {
  m_text += fmt::format("variable {:<20} string {:<23} # {}\n", name, value, note);
}

void write_text(const std::filesystem::path& path, const std::string& text) {
  {
    std::ifstream in(path, std::ios::binary);
    if (in) {
      const std::string old((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      if (old == text) return;
    }
  }
  util::write_file_atomically(path, text);
}

const std::string& template_text(const std::string& name) {
  const auto& all = embedded_templates();
  const auto it = all.find(name);
  assert(it != all.end() && "template missing from liggghts_templates/");
  return it->second;
}

std::string data_header(const std::string& title, long atoms, double half_x, double zlo, double zhi) {
  return data_header(title, atoms, -half_x, half_x, -half_x, half_x, zlo, zhi);
}

std::string data_header(const std::string& title, long atoms, double xlo, double xhi, double ylo, double yhi,
                        double zlo, double zhi) {
  return fmt::format(
      "{} (atom_style sphere: id type diameter density x y z)\n\n{} atoms\n2 atom types\n\n"
      "{:.10g} {:.10g} xlo xhi\n{:.10g} {:.10g} ylo yhi\n{:.10g} {:.10g} zlo zhi\n\nAtoms\n\n",
      title, atoms, xlo, xhi, ylo, yhi, zlo, zhi);
}

std::string atom_line(long id, const Particle& p, double density) {
  // Every data file is written particle by particle through here: a stop is seen within a few thousand of them.
  if (id % 4096 == 0) util::throw_if_stop_raised();
  // + 0.0 writes a negative zero as 0.
  return fmt::format("{} 1 {:.10g} {:.10g} {:.10g} {:.10g} {:.10g}\n", id, 2.0 * p.radius, density, p.x + 0.0,
                     p.y + 0.0, p.z + 0.0);
}

}  // namespace demsa::experiments
