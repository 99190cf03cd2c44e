// Opening a study's store for its study file (a new study's design drawn, a grown design or grown replicates added,
// a changed design refused) and `demsa extend` (the frozen study file's [design] samples rewritten, then opened).
#include "orchestrator/exec/open_study.hpp"

#include "orchestrator/exec/remeasure.hpp"
#include "orchestrator/exec/runner.hpp"
#include "orchestrator/experiments/registry.hpp"
#include "orchestrator/study/design_file.hpp"
#include "orchestrator/study/folder.hpp"
#include "orchestrator/study/settings.hpp"
#include "orchestrator/util/atomic_file.hpp"
#include "orchestrator/util/errors.hpp"
#include "orchestrator/util/text.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cctype>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace demsa::exec {

using namespace demsa::study;
using util::UserError;
using util::write_file_atomically;

namespace fs = std::filesystem;

namespace {

/// The replicates a stored study runs, as its study file said: P = the points with replicate cases, R = the largest
/// repeat + 1 (the point's own case is the first); none without replicate cases.
ReplicateSettings stored_replicates(const Store& store) {
  ReplicateSettings r;
  std::set<int> points;
  for (const ReplicateRow& row : store.replicates()) {
    points.insert(row.point);
    r.repeats = std::max(r.repeats, row.repeat + 1);
  }
  r.points = static_cast<int>(points.size());
  if (r.points == 0) r.repeats = 0;
  return r;
}

}  // namespace

Store open_study(const StudyConfig& config, const fs::path& study_file, const fs::path& dir, bool new_study,
                 bool dry_run, std::optional<RemeasureSummary>* remeasured) {
  const fs::path db = dir / k_store_file;
  if (new_study) {
    const std::string store = k_store_file;
    for (const std::string& name :
         {store, store + "-wal", store + "-shm", std::string(k_design_file), std::string(k_cases_folder),
          std::string(k_analysis_folder), std::string(k_cost_probe_file), std::string(k_cost_probe_folder)})
      fs::remove_all(dir / name);
  }
  Store store(db.string());
  const std::string hash = design_hash(config);
  if (const std::optional<std::string> stored = store.design_hash()) {
    // A raised [design] samples, or raised replicates, is growth: everything else hashes as the stored design.
    StudyConfig at_stored = config;
    at_stored.samples = store.design_samples();
    std::optional<StudyConfig> grown;
    if (*stored != hash) {
      if (design_hash(at_stored) == *stored) grown = at_stored;
      at_stored.replicates = stored_replicates(store);
      if (!grown && design_hash(at_stored) == *stored) grown = at_stored;
    }
    if (grown) {
      if (config.samples < grown->samples)
        throw UserError(fmt::format(
            "{}: [design] samples = {}, but the study in {} has {} design samples already; a design can grow, not "
            "shrink (its cases are run or reserved): set samples = {} or more, or start a new study with `demsa run "
            "--new` or another --dir",
            study_file.string(), config.samples, dir.string(), grown->samples, grown->samples));
      const ReplicateSettings& was = grown->replicates;
      if (config.replicates.points < was.points || (was.enabled() && config.replicates.repeats < was.repeats))
        throw UserError(fmt::format(
            "{}: [design] replicates = {}, but the study in {} has replicates = {{ points = {}, repeats = {} }} "
            "already; replicates can grow, not shrink (their cases are run or reserved): set points >= {} and "
            "repeats >= {}, or start a new study with `demsa run --new` or another --dir",
            study_file.string(),
            config.replicates.enabled()
                ? fmt::format("{{ points = {}, repeats = {} }}", config.replicates.points, config.replicates.repeats)
                : std::string("none"),
            dir.string(), was.points, was.repeats, was.points, was.repeats));
      if (config.samples > grown->samples) {
        const std::vector<SampleRow> existing = store.samples();
        const std::vector<SampleRow> added =
            design_extension(config, existing, grown->samples, config.samples - grown->samples);
        store.add_samples(added, "extended",
                          fmt::format("design {} grown from {} to {} samples (samples {} to {})", config.design,
                                      grown->samples, config.samples, added.front().sample, added.back().sample),
                          hash);
        write_file_atomically(dir / k_design_file, design_csv(config, store.samples()));
      } else {
        // Only the replicates grew: their cases are added below; the hash follows the study file first, so that a
        // demsa killed in between adds them on the next run as it would for a new study.
        store.add_samples({}, "extended",
                          fmt::format("replicates grown from {} points x {} repeats to {} x {}", was.points,
                                      was.repeats, config.replicates.points, config.replicates.repeats),
                          hash);
      }
    } else if (*stored != hash) {
      // The frozen copy is the last file the study accepted: it names the changed keys (when it still reads).
      std::optional<StudyConfig> before;
      try {
        before = experiments::load_study(dir / k_frozen_study);
      } catch (const UserError&) {
      }
      const std::vector<std::string> keys =
          before ? config.table->changed(*before, config) : std::vector<std::string>{};
      // Only how cases are measured changed (the frozen copy is the stored design, and the cases it writes are the
      // new file's): the finished cases are measured again from their files instead of refused.
      if (before && design_hash(*before) == *stored && cases_hash(*before) == cases_hash(config)) {
        if (remeasured)
          *remeasured = dry_run ? RemeasureSummary{0, 0, 0, keys} : remeasure_study(config, store, dir, keys);
        if (dry_run) return store;  // nothing written: the store and the frozen copy stay the study's
      } else {
        std::string changed;
        for (const std::string& key : keys) {
          changed += changed.empty() ? "; changed: " : ", ";
          changed += key;
        }
        throw UserError(fmt::format(
            "{}: the design-relevant settings differ from those of the study in {} (design hash {} there, {} now{}); "
            "only [run] and [analysis] may change in an existing study. Use `demsa run --new` to discard it and start "
            "a new study there, or choose another --dir",
            study_file.string(), dir.string(), *stored, hash, changed));
      }
    }
  } else {
    const std::vector<SampleRow> samples = draw_design(config);
    write_file_atomically(dir / k_design_file, design_csv(config, samples));
    store.initialize(hash, config.name, samples);
    store.add_event("created",
                    fmt::format("{} samples, design {}, seed {}", samples.size(), config.design, config.seed));
  }
  // The replicate cases: added on every open (a store that exists already keeps its rows), so a demsa killed between
  // initialize() and here adds them on the next run.
  if (config.replicates.enabled()) {
    const std::vector<ReplicateRow> replicates = replicate_rows(config, store.samples());
    if (store.replicates().size() != replicates.size()) {
      store.add_replicates(replicates);
      store.add_event("replicates",
                      fmt::format("{} replicate cases: {} points x {} repeats (the point's own case "
                                  "included), another assembly seed each",
                                  replicates.size(), config.replicates.points, config.replicates.repeats));
    }
  }
  // The frozen copy: the design part is identical by the hash check; [run]/[analysis] follow the latest file.
  const fs::path frozen = dir / k_frozen_study;
  std::error_code ec;
  if (!fs::equivalent(study_file, frozen, ec)) write_file_atomically(frozen, util::read_file(study_file));
  return store;
}

namespace {

/// The study text with the value of [design] samples replaced, or nothing when the file has no such line.
std::optional<std::string> with_samples(const std::string& text, int samples) {
  std::string out;
  std::string section;
  bool replaced = false;
  std::size_t start = 0;
  while (start < text.size()) {
    const std::size_t end = std::min(text.find('\n', start), text.size());
    std::string line = text.substr(start, end - start);
    const std::size_t first = line.find_first_not_of(" \t");
    if (first != std::string::npos && line[first] == '[') {
      const std::size_t close = line.find(']', first);
      section = close == std::string::npos ? "" : line.substr(first + 1, close - first - 1);
      section.erase(0, section.find_first_not_of(" \t"));
      section.erase(section.find_last_not_of(" \t") + 1);
    } else if (!replaced && section == "design" && first != std::string::npos &&
               line.compare(first, 7, "samples") == 0) {
      std::size_t at = first + 7;
      while (at < line.size() && (line[at] == ' ' || line[at] == '\t')) ++at;
      if (at < line.size() && line[at] == '=') {
        ++at;
        while (at < line.size() && (line[at] == ' ' || line[at] == '\t')) ++at;
        std::size_t digits = at;
        while (digits < line.size() && std::isdigit(static_cast<unsigned char>(line[digits]))) ++digits;
        if (digits > at) {
          line = line.substr(0, at) + std::to_string(samples) + line.substr(digits);
          replaced = true;
        }
      }
    }
    out += line;
    if (end < text.size()) out += '\n';
    start = end + 1;
  }
  if (!replaced) return std::nullopt;
  return out;
}

}  // namespace

namespace {

/// The design of the study in `dir` grown to `samples` points; the number added.
int grow_design(const fs::path& dir, int samples) {
  require_study_folder(dir);
  const StudyLock lock(dir);
  const fs::path frozen = dir / k_frozen_study;
  const StudyConfig before = experiments::load_study(frozen);
  int design = 0;
  {
    const Store store((dir / k_store_file).string());
    if (const std::optional<std::string> stored = store.design_hash()) {
      design = store.design_samples();
      StudyConfig at_stored = before;
      at_stored.samples = design;
      if (design_hash(at_stored) != *stored)
        throw UserError(
            fmt::format("{}: the study file there no longer matches its store (design hash {} stored, {} "
                        "for the file); `demsa run` with the study's own file repairs or refuses it",
                        frozen.string(), *stored, design_hash(at_stored)));
    } else {
      throw UserError(fmt::format("{}: the store holds no design yet; `demsa run` creates it", dir.string()));
    }
  }
  if (samples < design)
    throw UserError(
        fmt::format("ExtendOptions.samples {}: the study in {} has {} design samples already; a design can grow, not "
                    "shrink",
                    samples, dir.string(), design));
  const std::optional<std::string> text = with_samples(util::read_file(frozen), samples);
  if (!text) throw UserError(fmt::format("{}: no `samples = N` line in its [design] section", frozen.string()));
  // The new file is read as a study file (bounds of samples, e.g. at most 4096 for an optimised LHS) before the
  // store changes; open_study then extends the store and writes it as the frozen copy.
  const fs::path candidate = dir / ".study.extend.toml";
  write_file_atomically(candidate, *text);
  StudyConfig after;
  try {
    after = experiments::load_study(candidate);
  } catch (const UserError& e) {
    fs::remove(candidate);
    throw UserError(fmt::format("ExtendOptions.samples {}: {}", samples, e.what()));
  }
  { Store store = open_study(after, candidate, dir, false); }
  fs::remove(candidate);
  return samples - design;
}

}  // namespace

Extension extend_study(const ExtendOptions& options) {
  Extension e;
  e.dir = options.dir;
  e.added = grow_design(options.dir, options.samples);
  const Store store = Store::open_read_only((options.dir / k_store_file).string());
  e.design_samples = store.design_samples();
  e.all_samples = store.samples().size();
  return e;
}

std::string extension_text(const Extension& e) {
  if (e.added == 0)
    return fmt::format("{}: the design has {} samples already; nothing added\n", e.dir.string(), e.design_samples);
  return fmt::format(
      "{}: {} design samples added (now {} design samples, {} in all); `demsa run {} --dir {}` runs them\n",
      e.dir.string(), e.added, e.design_samples, e.all_samples, (e.dir / k_frozen_study).string(), e.dir.string());
}

}  // namespace demsa::exec
