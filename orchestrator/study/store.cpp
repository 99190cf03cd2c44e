#include "orchestrator/study/store.hpp"

#include "orchestrator/util/errors.hpp"
#include "postprocess/text.hpp"
#include "sobol/enum_names.hpp"

#include <SQLiteCpp/SQLiteCpp.h>
#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <utility>

namespace demsa::study {

namespace {

constexpr int k_busy_timeout_ms = 30000;

const sobol::EnumNames<RunState>& run_state_names() {
  static const sobol::EnumNames<RunState> names{"run state",
                                                {{RunState::submitted, "submitted"},
                                                 {RunState::done, "done"},
                                                 {RunState::failed, "failed"},
                                                 {RunState::requeued, "requeued"}}};
  return names;
}

constexpr const char* k_run_columns =
    "id, sample, attempt, state, job_id, exit_code, signal, failure, message, wall_seconds, cpu_seconds, host, "
    "log_tail, submitted_at, finished_at";

// The runs table of schema version 2, named `table` (the migration builds it as runs_v2, then renames it). The
// failure names are those of FailureClass when version 2 was made: a new class is a new schema version, because a
// CHECK constraint cannot change without rebuilding the table (tests/orchestrator/study/test_store.cpp stores
// every class).
std::string runs_table(const char* table) {
  return fmt::format(R"sql(
CREATE TABLE IF NOT EXISTS {} (
  id INTEGER PRIMARY KEY AUTOINCREMENT,
  sample INTEGER NOT NULL REFERENCES samples(sample),
  attempt INTEGER NOT NULL,
  state TEXT NOT NULL CHECK (state IN ('submitted', 'done', 'failed', 'requeued')),
  job_id TEXT NOT NULL DEFAULT '',
  exit_code INTEGER NOT NULL DEFAULT -1,
  signal INTEGER NOT NULL DEFAULT 0,
  failure TEXT NOT NULL DEFAULT 'none' CHECK (failure IN ('none', 'nonzero-exit', 'signal', 'timeout',
    'liggghts-error', 'lost-particles', 'energy-blowup', 'missing-dump', 'plate-not-converged', 'measurement')),
  message TEXT NOT NULL DEFAULT '',
  wall_seconds REAL NOT NULL DEFAULT 0,
  cpu_seconds REAL NOT NULL DEFAULT 0,
  host TEXT NOT NULL DEFAULT '',
  log_tail TEXT NOT NULL DEFAULT '',
  submitted_at REAL NOT NULL,
  finished_at REAL NOT NULL DEFAULT 0,
  CHECK (state = 'failed' OR failure = 'none'));
)sql",
                     table);
}

// Runs and observables are append-mostly; the partial unique index makes "done twice" impossible.
std::string schema() {
  return R"sql(
CREATE TABLE IF NOT EXISTS meta (key TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS samples (
  sample INTEGER PRIMARY KEY,
  unit TEXT NOT NULL,
  physical TEXT NOT NULL);
)sql" + runs_table("runs") +
         R"sql(
CREATE UNIQUE INDEX IF NOT EXISTS runs_one_done ON runs(sample) WHERE state = 'done';
CREATE INDEX IF NOT EXISTS runs_by_sample ON runs(sample);
CREATE TABLE IF NOT EXISTS observables (
  sample INTEGER NOT NULL REFERENCES samples(sample),
  name TEXT NOT NULL,
  value REAL NOT NULL,
  run INTEGER NOT NULL REFERENCES runs(id),
  PRIMARY KEY (sample, name));
CREATE TABLE IF NOT EXISTS refine_history (
  samples INTEGER PRIMARY KEY,
  iteration INTEGER NOT NULL,
  target REAL NOT NULL,
  time REAL NOT NULL,
  decision TEXT NOT NULL,
  max_half_width TEXT NOT NULL,
  indices TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS replicates (
  sample INTEGER PRIMARY KEY REFERENCES samples(sample),
  point INTEGER NOT NULL REFERENCES samples(sample),
  repeat INTEGER NOT NULL,
  seed TEXT NOT NULL,
  UNIQUE (point, repeat));
CREATE TABLE IF NOT EXISTS case_costs (
  run INTEGER PRIMARY KEY REFERENCES runs(id),
  sample INTEGER NOT NULL REFERENCES samples(sample),
  cap_atom_steps REAL NOT NULL,
  predicted_atom_steps REAL NOT NULL,
  predicted_cpu_seconds REAL NOT NULL,
  atom_steps REAL NOT NULL,
  cpu_seconds REAL NOT NULL);
CREATE TABLE IF NOT EXISTS events (
  id INTEGER PRIMARY KEY AUTOINCREMENT,
  time REAL NOT NULL,
  kind TEXT NOT NULL,
  sample INTEGER NOT NULL DEFAULT -1,
  message TEXT NOT NULL);
)sql";
}

bool has_table(SQLite::Database& db, const char* name) {
  SQLite::Statement q(db, "SELECT 1 FROM sqlite_master WHERE type = 'table' AND name = ?");
  q.bind(1, name);
  return q.executeStep();
}

// The schema version of the file: 0 for a database without tables (a new store). Refuses a newer version and a
// database that is not a study store.
int read_schema_version(SQLite::Database& db) {
  const std::string path = db.getFilename();
  if (!has_table(db, "meta")) {
    if (!has_table(db, "runs") && !has_table(db, "samples")) return 0;
    throw util::UserError(fmt::format("{}: not a demsa study store (no meta table)", path));
  }
  SQLite::Statement q(db, "SELECT value FROM meta WHERE key = 'schema_version'");
  if (!q.executeStep()) throw util::UserError(fmt::format("{}: not a demsa study store (no schema version)", path));
  const std::string text = q.getColumn(0).getString();
  int version = 0;
  try {
    std::size_t used = 0;
    version = std::stoi(text, &used);
    if (used != text.size()) version = 0;
  } catch (const std::exception&) {
    version = 0;
  }
  if (version < 1) throw util::UserError(fmt::format("{}: not a demsa study store (schema version '{}')", path, text));
  if (version > k_store_schema_version)
    throw util::UserError(
        fmt::format("{}: study store of schema version {}, written by a newer demsa; this demsa reads versions up to "
                    "{}: use the demsa that wrote it",
                    path, version, k_store_schema_version));
  return version;
}

// Version 1 -> 2: rebuilds runs with the CHECK constraints (SQLite cannot add a constraint to a table; the rebuild
// follows "Making Other Kinds Of Table Schema Changes" of https://www.sqlite.org/lang_altertable.html: foreign keys
// off outside the transaction, new table, copy, drop, rename, foreign_key_check, commit). One transaction: either
// the file is version 2 or it is as it was.
void migrate_from_version_1(SQLite::Database& db) {
  const std::string path = db.getFilename();
  db.exec("PRAGMA foreign_keys = OFF");
  SQLite::Transaction tx(db, SQLite::TransactionBehavior::IMMEDIATE);
  if (read_schema_version(db) != 1) return;  // another demsa migrated it first
  {
    SQLite::Statement names(db, "SELECT DISTINCT failure FROM runs WHERE state = 'failed' AND failure <> ''");
    while (names.executeStep()) {
      try {
        (void)failure_class_from_string(names.getColumn(0).getString());
      } catch (const std::invalid_argument& e) {
        throw util::UserError(
            fmt::format("{}: a failed run of this study store (schema version 1): {}", path, e.what()));
      }
    }
  }
  std::int64_t sequence = 0;
  {
    SQLite::Statement q(db, "SELECT seq FROM sqlite_sequence WHERE name = 'runs'");
    if (q.executeStep()) sequence = q.getColumn(0).getInt64();
  }
  db.exec(runs_table("runs_v2"));
  db.exec(
      fmt::format("INSERT INTO runs_v2 ({0}) SELECT id, sample, attempt, state, job_id, exit_code, signal, "
                  "CASE WHEN state = 'failed' AND failure <> '' THEN failure ELSE 'none' END, message, wall_seconds, "
                  "cpu_seconds, host, log_tail, submitted_at, finished_at FROM runs",
                  k_run_columns));
  db.exec("DROP TABLE runs");
  db.exec("ALTER TABLE runs_v2 RENAME TO runs");
  db.exec(schema());  // the indexes went with the old table
  {
    SQLite::Statement q(db, "UPDATE sqlite_sequence SET seq = max(seq, ?) WHERE name = 'runs'");
    q.bind(1, sequence);
    q.exec();
  }
  {
    SQLite::Statement check(db, "PRAGMA foreign_key_check");
    if (check.executeStep())
      throw util::InternalError(fmt::format("{}: migration to schema version 2 broke a foreign key (table {})", path,
                                            check.getColumn(0).getString()));
  }
  SQLite::Statement meta(db, "UPDATE meta SET value = ? WHERE key = 'schema_version'");
  meta.bind(1, std::to_string(k_store_schema_version));
  meta.exec();
  SQLite::Statement event(db, "INSERT INTO events(time, kind, sample, message) VALUES (?, 'migrated', -1, ?)");
  event.bind(1, unix_now());
  event.bind(2, fmt::format("store schema version 1 -> {}: failure classes checked, none for runs that did not fail",
                            k_store_schema_version));
  event.exec();
  tx.commit();
}

std::string to_json(const std::vector<double>& values) { return nlohmann::json(values).dump(); }

std::vector<double> from_json(const std::string& text) {
  return nlohmann::json::parse(text).get<std::vector<double>>();
}

RunRow read_run(SQLite::Statement& q) {
  RunRow row;
  row.id = q.getColumn(0).getInt64();
  row.sample = q.getColumn(1).getInt();
  row.attempt = q.getColumn(2).getInt();
  row.state = run_state_from_string(q.getColumn(3).getString());
  row.job_id = q.getColumn(4).getString();
  row.exit_code = q.getColumn(5).getInt();
  row.signal = q.getColumn(6).getInt();
  // "" is a version-1 store read as it is (read-only open): a run that did not fail.
  const std::string failure = q.getColumn(7).getString();
  row.failure = failure.empty() ? FailureClass::none : failure_class_from_string(failure);
  row.message = q.getColumn(8).getString();
  row.wall_seconds = q.getColumn(9).getDouble();
  row.cpu_seconds = q.getColumn(10).getDouble();
  row.host = q.getColumn(11).getString();
  row.log_tail = q.getColumn(12).getString();
  row.submitted_at = q.getColumn(13).getDouble();
  row.finished_at = q.getColumn(14).getDouble();
  return row;
}

void bind_outcome(SQLite::Statement& q, const RunOutcome& o) {
  q.bind(":exit_code", o.exit_code);
  q.bind(":signal", o.signal);
  q.bind(":failure", to_string(o.failure));
  q.bind(":message", o.message);
  q.bind(":wall", o.wall_seconds);
  q.bind(":cpu", o.cpu_seconds);
  q.bind(":host", o.host);
  q.bind(":tail", o.log_tail);
  q.bind(":finished", unix_now());
}

constexpr const char* k_update_outcome =
    "UPDATE runs SET state = :state, exit_code = :exit_code, signal = :signal, failure = :failure, "
    "message = :message, wall_seconds = :wall, cpu_seconds = :cpu, host = :host, log_tail = :tail, "
    "finished_at = :finished WHERE id = :id AND state = 'submitted'";

/// The observables of `run` of `sample`, each replacing the sample's value of that name (record_done and
/// record_remeasured).
void insert_observables(SQLite::Database& db, int sample, long run, const std::map<std::string, double>& observables) {
  SQLite::Statement insert(db, "INSERT OR REPLACE INTO observables(sample, name, value, run) VALUES (?, ?, ?, ?)");
  for (const auto& [name, value] : observables) {
    insert.bind(1, sample);
    insert.bind(2, name);
    insert.bind(3, value);
    insert.bind(4, static_cast<std::int64_t>(run));
    insert.exec();
    insert.reset();
  }
}

}  // namespace

std::string to_string(RunState state) {
  const std::string name = run_state_names().to_string(state);
  return name.empty() ? "unknown" : name;
}

RunState run_state_from_string(const std::string& name) {
  if (const auto state = run_state_names().find(name)) return *state;
  throw std::invalid_argument(run_state_names().unknown(name));
}

double unix_now() { return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count(); }

namespace {

/// Opens the database and reads its schema version once, so that a file that is not a database, or cannot be
/// opened, fails here with its path in the message (SQLite's own messages do not name the file).
std::unique_ptr<SQLite::Database> open_database(const std::string& path, int flags) {
  // SQLite would open a FIFO or a device and wait in its first read.
  if (const std::optional<std::string> kind = postprocess::special_file_kind(path))
    throw util::UserError(path, 0, postprocess::special_file_message(*kind));
  try {
    auto db = std::make_unique<SQLite::Database>(path, flags, k_busy_timeout_ms);
    db->exec("SELECT count(*) FROM sqlite_master");
    return db;
  } catch (const SQLite::Exception& e) {
    throw util::InternalError(fmt::format("{}: cannot open the study store (SQLite: {})", path, e.what()));
  }
}

}  // namespace

Store::Store(const std::string& path) : m_db(open_database(path, SQLite::OPEN_READWRITE | SQLite::OPEN_CREATE)) {
  // Creating the tables is the first write: a full disk or a read-only folder fails here, named like an open error.
  try {
    create_or_migrate();
  } catch (const SQLite::Exception& e) {
    throw util::InternalError(fmt::format("{}: cannot open the study store (SQLite: {})", path, e.what()));
  }
}

void Store::create_or_migrate() {
  m_db->exec("PRAGMA journal_mode = WAL");
  // FULL: a transaction that returned is on disk, also after a power cut (SIGKILL alone would need only NORMAL).
  m_db->exec("PRAGMA synchronous = FULL");
  // Before foreign_keys = ON: the migration turns them off, and that pragma is a no-op inside a transaction.
  if (read_schema_version(*m_db) == 1) migrate_from_version_1(*m_db);
  m_db->exec("PRAGMA foreign_keys = ON");
  SQLite::Transaction tx(*m_db, SQLite::TransactionBehavior::IMMEDIATE);
  m_db->exec(schema());
  SQLite::Statement q(*m_db, "INSERT OR IGNORE INTO meta(key, value) VALUES ('schema_version', ?)");
  q.bind(1, std::to_string(k_store_schema_version));
  q.exec();
  tx.commit();
}

Store::Store(std::unique_ptr<SQLite::Database> db) : m_db(std::move(db)) {}

Store Store::open_read_only(const std::string& path) {
  if (!std::filesystem::exists(path)) throw util::UserError(fmt::format("{}: no study store here", path));
  auto db = open_database(path, SQLite::OPEN_READONLY);
  if (read_schema_version(*db) == 0) throw util::UserError(fmt::format("{}: not a demsa study store (empty)", path));
  return Store(std::move(db));
}

int Store::schema_version() const { return read_schema_version(*m_db); }

Store::~Store() = default;
Store::Store(Store&&) noexcept = default;
Store& Store::operator=(Store&&) noexcept = default;

std::optional<std::string> Store::design_hash() const {
  SQLite::Statement q(*m_db, "SELECT value FROM meta WHERE key = 'design_hash'");
  if (q.executeStep()) return q.getColumn(0).getString();
  return std::nullopt;
}

std::string Store::study_name() const {
  SQLite::Statement q(*m_db, "SELECT value FROM meta WHERE key = 'study_name'");
  return q.executeStep() ? q.getColumn(0).getString() : std::string{};
}

void Store::initialize(const std::string& hash, const std::string& study_name, const std::vector<SampleRow>& samples) {
  SQLite::Transaction tx(*m_db, SQLite::TransactionBehavior::IMMEDIATE);
  {
    SQLite::Statement check(*m_db, "SELECT count(*) FROM samples");
    check.executeStep();
    if (check.getColumn(0).getInt() != 0) throw std::logic_error("Store::initialize on a store that has samples");
  }
  SQLite::Statement meta(*m_db, "INSERT OR REPLACE INTO meta(key, value) VALUES (?, ?)");
  for (const auto& [key, value] : {std::pair<std::string, std::string>{"design_hash", hash},
                                   {"study_name", study_name},
                                   {"created_at", fmt::format("{:.3f}", unix_now())}}) {
    meta.bind(1, key);
    meta.bind(2, value);
    meta.exec();
    meta.reset();
  }
  SQLite::Statement insert(*m_db, "INSERT INTO samples(sample, unit, physical) VALUES (?, ?, ?)");
  for (const SampleRow& s : samples) {
    insert.bind(1, s.sample);
    insert.bind(2, to_json(s.unit));
    insert.bind(3, to_json(s.physical));
    insert.exec();
    insert.reset();
  }
  tx.commit();
}

int replicate_sample_id(int point, int repeat) {
  if (point < 0 || point >= 100000 || repeat < 1 || repeat >= k_max_replicate_repeats)
    throw std::logic_error(fmt::format("replicate_sample_id: point {} repeat {} out of range", point, repeat));
  return k_replicate_sample_base + point * k_max_replicate_repeats + repeat;
}

void Store::add_replicates(const std::vector<ReplicateRow>& replicates) {
  if (replicates.empty()) return;
  SQLite::Transaction tx(*m_db, SQLite::TransactionBehavior::IMMEDIATE);
  SQLite::Statement sample(*m_db, "INSERT OR IGNORE INTO samples(sample, unit, physical) VALUES (?, ?, ?)");
  SQLite::Statement replicate(*m_db,
                              "INSERT OR IGNORE INTO replicates(sample, point, repeat, seed) VALUES (?, ?, ?, ?)");
  for (const ReplicateRow& r : replicates) {
    sample.bind(1, r.sample);
    sample.bind(2, to_json(r.unit));
    sample.bind(3, to_json(r.physical));
    sample.exec();
    sample.reset();
    replicate.bind(1, r.sample);
    replicate.bind(2, r.point);
    replicate.bind(3, r.repeat);
    replicate.bind(4, std::to_string(r.seed));  // text: SQLite integers are signed
    replicate.exec();
    replicate.reset();
  }
  tx.commit();
}

std::vector<ReplicateRow> Store::replicates() const {
  std::vector<ReplicateRow> rows;
  if (!has_table(*m_db, "replicates")) return rows;  // a store of a demsa before replicates, opened read-only
  SQLite::Statement q(*m_db,
                      "SELECT r.sample, r.point, r.repeat, r.seed, s.unit, s.physical FROM replicates r "
                      "JOIN samples s ON s.sample = r.sample ORDER BY r.point, r.repeat");
  while (q.executeStep()) {
    ReplicateRow row;
    row.sample = q.getColumn(0).getInt();
    row.point = q.getColumn(1).getInt();
    row.repeat = q.getColumn(2).getInt();
    row.seed = std::stoull(q.getColumn(3).getString());
    row.unit = from_json(q.getColumn(4).getString());
    row.physical = from_json(q.getColumn(5).getString());
    rows.push_back(std::move(row));
  }
  return rows;
}

std::vector<SampleRow> Store::samples() const {
  std::vector<SampleRow> rows;
  SQLite::Statement q(*m_db, has_table(*m_db, "replicates")
                                 ? "SELECT sample, unit, physical FROM samples WHERE sample NOT IN "
                                   "(SELECT sample FROM replicates) ORDER BY sample"
                                 : "SELECT sample, unit, physical FROM samples ORDER BY sample");
  while (q.executeStep())
    rows.push_back(
        {q.getColumn(0).getInt(), from_json(q.getColumn(1).getString()), from_json(q.getColumn(2).getString())});
  return rows;
}

int Store::design_samples() const {
  SQLite::Statement q(*m_db, "SELECT value FROM meta WHERE key = 'design_samples'");
  if (q.executeStep()) return std::stoi(q.getColumn(0).getString());
  return static_cast<int>(samples().size());  // replicate cases are not design samples
}

void Store::add_samples(const std::vector<SampleRow>& samples, const std::string& kind, const std::string& message,
                        const std::optional<std::string>& design_hash) {
  const int design = design_samples();
  SQLite::Transaction tx(*m_db, SQLite::TransactionBehavior::IMMEDIATE);
  // Indices continue the design's and refinement's samples; replicate cases have ids of their own, far above.
  const std::vector<SampleRow> existing = this->samples();
  int next = existing.empty() ? 0 : existing.back().sample + 1;
  SQLite::Statement insert(*m_db, "INSERT INTO samples(sample, unit, physical) VALUES (?, ?, ?)");
  for (const SampleRow& s : samples) {
    if (s.sample != next)
      throw std::logic_error(fmt::format("Store::add_samples: sample {} after {}", s.sample, next - 1));
    insert.bind(1, s.sample);
    insert.bind(2, to_json(s.unit));
    insert.bind(3, to_json(s.physical));
    insert.exec();
    insert.reset();
    ++next;
  }
  SQLite::Statement meta(*m_db, "INSERT OR REPLACE INTO meta(key, value) VALUES (?, ?)");
  const auto set_meta = [&](const std::string& key, const std::string& value) {
    meta.bind(1, key);
    meta.bind(2, value);
    meta.exec();
    meta.reset();
  };
  if (design_hash) {
    set_meta("design_hash", *design_hash);
    set_meta("design_samples", std::to_string(design + static_cast<int>(samples.size())));
  } else {
    set_meta("design_samples", std::to_string(design));
  }
  SQLite::Statement event(*m_db, "INSERT INTO events(time, kind, sample, message) VALUES (?, ?, -1, ?)");
  event.bind(1, unix_now());
  event.bind(2, kind);
  event.bind(3, message);
  event.exec();
  tx.commit();
}

void Store::record_refine_step(const RefineStep& step) {
  SQLite::Statement q(*m_db,
                      "INSERT OR REPLACE INTO refine_history(samples, iteration, target, time, decision, "
                      "max_half_width, indices) VALUES (?, ?, ?, ?, ?, ?, ?)");
  nlohmann::json widths = nlohmann::json::object();
  for (const auto& [name, w] : step.max_half_width)
    widths[name] = std::isfinite(w) ? nlohmann::json(w) : nlohmann::json(nullptr);
  q.bind(1, step.samples);
  q.bind(2, step.iteration);
  q.bind(3, step.target);
  q.bind(4, step.time);
  q.bind(5, step.decision);
  q.bind(6, widths.dump());
  q.bind(7, step.indices_json);
  q.exec();
}

std::vector<RefineStep> Store::refine_history() const {
  std::vector<RefineStep> steps;
  if (!has_table(*m_db, "refine_history")) return steps;
  SQLite::Statement q(*m_db,
                      "SELECT samples, iteration, target, time, decision, max_half_width, indices FROM refine_history "
                      "ORDER BY samples");
  while (q.executeStep()) {
    RefineStep s;
    s.samples = q.getColumn(0).getInt();
    s.iteration = q.getColumn(1).getInt();
    s.target = q.getColumn(2).getDouble();
    s.time = q.getColumn(3).getDouble();
    s.decision = q.getColumn(4).getString();
    const nlohmann::json widths = nlohmann::json::parse(q.getColumn(5).getString());
    for (const auto& [name, w] : widths.items())
      s.max_half_width[name] = w.is_null() ? std::numeric_limits<double>::quiet_NaN() : w.get<double>();
    s.indices_json = q.getColumn(6).getString();
    steps.push_back(std::move(s));
  }
  return steps;
}

void Store::record_case_cost(const CaseCostRow& row) {
  SQLite::Statement q(*m_db,
                      "INSERT OR REPLACE INTO case_costs(run, sample, cap_atom_steps, predicted_atom_steps, "
                      "predicted_cpu_seconds, atom_steps, cpu_seconds) VALUES (?, ?, ?, ?, ?, ?, ?)");
  q.bind(1, static_cast<int64_t>(row.run));
  q.bind(2, row.sample);
  q.bind(3, row.cap_atom_steps);
  q.bind(4, row.predicted_atom_steps);
  q.bind(5, row.predicted_cpu_seconds);
  q.bind(6, row.atom_steps);
  q.bind(7, row.cpu_seconds);
  q.exec();
}

std::vector<CaseCostRow> Store::case_costs() const {
  std::vector<CaseCostRow> rows;
  if (!has_table(*m_db, "case_costs")) return rows;
  SQLite::Statement q(*m_db,
                      "SELECT run, sample, cap_atom_steps, predicted_atom_steps, predicted_cpu_seconds, atom_steps, "
                      "cpu_seconds FROM case_costs ORDER BY run");
  while (q.executeStep()) {
    CaseCostRow r;
    r.run = q.getColumn(0).getInt64();
    r.sample = q.getColumn(1).getInt();
    r.cap_atom_steps = q.getColumn(2).getDouble();
    r.predicted_atom_steps = q.getColumn(3).getDouble();
    r.predicted_cpu_seconds = q.getColumn(4).getDouble();
    r.atom_steps = q.getColumn(5).getDouble();
    r.cpu_seconds = q.getColumn(6).getDouble();
    rows.push_back(r);
  }
  return rows;
}

long Store::add_run(int sample, int attempt) {
  SQLite::Statement q(*m_db, "INSERT INTO runs(sample, attempt, state, submitted_at) VALUES (?, ?, 'submitted', ?)");
  q.bind(1, sample);
  q.bind(2, attempt);
  q.bind(3, unix_now());
  q.exec();
  return static_cast<long>(m_db->getLastInsertRowid());
}

std::vector<long> Store::add_runs(const std::vector<NewRun>& runs) {
  std::vector<long> ids;
  SQLite::Transaction tx(*m_db, SQLite::TransactionBehavior::IMMEDIATE);
  SQLite::Statement q(
      *m_db, "INSERT INTO runs(sample, attempt, state, job_id, submitted_at) VALUES (?, ?, 'submitted', ?, ?)");
  const double now = unix_now();
  for (const NewRun& r : runs) {
    q.bind(1, r.sample);
    q.bind(2, r.attempt);
    q.bind(3, r.job_id);
    q.bind(4, now);
    q.exec();
    q.reset();
    ids.push_back(static_cast<long>(m_db->getLastInsertRowid()));
  }
  tx.commit();
  return ids;
}

void Store::set_job_ids(const std::vector<std::pair<long, std::string>>& ids) {
  SQLite::Transaction tx(*m_db, SQLite::TransactionBehavior::IMMEDIATE);
  SQLite::Statement q(*m_db, "UPDATE runs SET job_id = ? WHERE id = ?");
  for (const auto& [run, job_id] : ids) {
    q.bind(1, job_id);
    q.bind(2, static_cast<std::int64_t>(run));
    q.exec();
    q.reset();
  }
  tx.commit();
}

void Store::set_job_id(long run, const std::string& job_id) {
  SQLite::Statement q(*m_db, "UPDATE runs SET job_id = ? WHERE id = ?");
  q.bind(1, job_id);
  q.bind(2, static_cast<std::int64_t>(run));
  q.exec();
}

void Store::record_done(long run, const RunOutcome& outcome, const std::map<std::string, double>& observables) {
  if (outcome.failure != FailureClass::none)
    throw std::logic_error(fmt::format("record_done: run {} has failure class {}", run, to_string(outcome.failure)));
  SQLite::Transaction tx(*m_db, SQLite::TransactionBehavior::IMMEDIATE);
  int sample = -1;
  {
    SQLite::Statement q(*m_db, "SELECT sample FROM runs WHERE id = ? AND state = 'submitted'");
    q.bind(1, static_cast<std::int64_t>(run));
    if (!q.executeStep()) throw std::logic_error(fmt::format("record_done: run {} is not in state submitted", run));
    sample = q.getColumn(0).getInt();
  }
  SQLite::Statement update(*m_db, k_update_outcome);
  update.bind(":state", "done");
  bind_outcome(update, outcome);
  update.bind(":id", static_cast<std::int64_t>(run));
  update.exec();  // the unique index throws if the sample is already done
  insert_observables(*m_db, sample, run, observables);
  SQLite::Statement event(*m_db, "INSERT INTO events(time, kind, sample, message) VALUES (?, 'done', ?, ?)");
  event.bind(1, unix_now());
  event.bind(2, sample);
  event.bind(3, fmt::format("run {} done in {:.1f} s", run, outcome.wall_seconds));
  event.exec();
  tx.commit();
}

void Store::record_failed(long run, const RunOutcome& outcome) {
  if (outcome.failure == FailureClass::none)
    throw std::logic_error(fmt::format("record_failed: run {} without a failure class", run));
  SQLite::Transaction tx(*m_db, SQLite::TransactionBehavior::IMMEDIATE);
  SQLite::Statement update(*m_db, k_update_outcome);
  update.bind(":state", "failed");
  bind_outcome(update, outcome);
  update.bind(":id", static_cast<std::int64_t>(run));
  if (update.exec() != 1) throw std::logic_error(fmt::format("record_failed: run {} is not in state submitted", run));
  SQLite::Statement event(*m_db,
                          "INSERT INTO events(time, kind, sample, message) "
                          "SELECT ?, 'failed', sample, ? FROM runs WHERE id = ?");
  event.bind(1, unix_now());
  event.bind(2, fmt::format("run {}: {}: {}", run, to_string(outcome.failure), outcome.message));
  event.bind(3, static_cast<std::int64_t>(run));
  event.exec();
  tx.commit();
}

void Store::record_requeued(long run, const std::string& message) {
  SQLite::Statement q(*m_db,
                      "UPDATE runs SET state = 'requeued', message = ?, finished_at = ? "
                      "WHERE id = ? AND state = 'submitted'");
  q.bind(1, message);
  q.bind(2, unix_now());
  q.bind(3, static_cast<std::int64_t>(run));
  q.exec();
}

void Store::record_remeasured(const std::string& design_hash, const std::vector<RemeasuredCase>& cases,
                              const std::string& message) {
  SQLite::Transaction tx(*m_db, SQLite::TransactionBehavior::IMMEDIATE);
  SQLite::Statement find(*m_db, "SELECT sample FROM runs WHERE id = ? AND state IN ('done', 'failed')");
  SQLite::Statement forget(*m_db, "DELETE FROM observables WHERE sample = ?");
  SQLite::Statement done(*m_db, "UPDATE runs SET state = 'done', failure = 'none', message = ? WHERE id = ?");
  SQLite::Statement failed(*m_db,
                           "UPDATE runs SET state = 'failed', failure = 'measurement', message = ? WHERE id = ?");
  for (const RemeasuredCase& c : cases) {
    find.bind(1, static_cast<std::int64_t>(c.run));
    if (!find.executeStep())
      throw std::logic_error(fmt::format("record_remeasured: run {} is neither done nor failed", c.run));
    const int sample = find.getColumn(0).getInt();
    find.reset();
    forget.bind(1, sample);
    forget.exec();
    forget.reset();
    SQLite::Statement& update = c.observables ? done : failed;
    update.bind(1, c.message);
    update.bind(2, static_cast<std::int64_t>(c.run));
    update.exec();  // the unique index throws if another run of the sample is done
    update.reset();
    if (c.observables) insert_observables(*m_db, sample, c.run, *c.observables);
  }
  SQLite::Statement meta(*m_db, "INSERT OR REPLACE INTO meta(key, value) VALUES ('design_hash', ?)");
  meta.bind(1, design_hash);
  meta.exec();
  SQLite::Statement event(*m_db, "INSERT INTO events(time, kind, sample, message) VALUES (?, 'remeasured', -1, ?)");
  event.bind(1, unix_now());
  event.bind(2, message);
  event.exec();
  tx.commit();
}

std::vector<RunRow> Store::runs() const {
  std::vector<RunRow> rows;
  SQLite::Statement q(*m_db, fmt::format("SELECT {} FROM runs ORDER BY id", k_run_columns));
  while (q.executeStep()) rows.push_back(read_run(q));
  return rows;
}

std::vector<RunRow> Store::runs_in_state(RunState state) const {
  std::vector<RunRow> rows;
  SQLite::Statement q(*m_db, fmt::format("SELECT {} FROM runs WHERE state = ? ORDER BY id", k_run_columns));
  q.bind(1, to_string(state));
  while (q.executeStep()) rows.push_back(read_run(q));
  return rows;
}

std::optional<RunRow> Store::run(long id) const {
  SQLite::Statement q(*m_db, fmt::format("SELECT {} FROM runs WHERE id = ?", k_run_columns));
  q.bind(1, static_cast<std::int64_t>(id));
  if (q.executeStep()) return read_run(q);
  return std::nullopt;
}

std::map<int, std::map<std::string, double>> Store::observables() const {
  std::map<int, std::map<std::string, double>> values;
  SQLite::Statement q(*m_db, "SELECT sample, name, value FROM observables ORDER BY sample, name");
  while (q.executeStep()) values[q.getColumn(0).getInt()][q.getColumn(1).getString()] = q.getColumn(2).getDouble();
  return values;
}

StoreCounts Store::counts() const {
  StoreCounts c;
  // The state of a sample is the state of its latest run (a done run is always the latest: nothing runs after it).
  const bool replicates = has_table(*m_db, "replicates");
  SQLite::Statement q(*m_db, fmt::format("SELECT s.sample, (SELECT state FROM runs r WHERE r.sample = s.sample ORDER "
                                         "BY id DESC LIMIT 1), {} FROM samples s",
                                         replicates ? "s.sample IN (SELECT sample FROM replicates)" : "0"));
  while (q.executeStep()) {
    const std::string state = q.getColumn(1).isNull() ? std::string{} : q.getColumn(1).getString();
    if (q.getColumn(2).getInt() != 0) {
      ++c.replicates;
      c.replicates_done += state == "done";
      c.replicates_running += state == "submitted";
      c.replicates_failed += state == "failed";
      continue;
    }
    ++c.samples;
    if (state == "done")
      ++c.done;
    else if (state == "submitted")
      ++c.running;
    else if (state == "failed")
      ++c.failed;
    else
      ++c.pending;
  }
  SQLite::Statement a(*m_db, "SELECT count(*), (SELECT avg(wall_seconds) FROM runs WHERE state = 'done') FROM runs");
  a.executeStep();
  c.attempts = a.getColumn(0).getInt();
  c.mean_done_wall = a.getColumn(1).isNull() ? 0.0 : a.getColumn(1).getDouble();
  return c;
}

void Store::add_event(const std::string& kind, const std::string& message, int sample) {
  SQLite::Statement q(*m_db, "INSERT INTO events(time, kind, sample, message) VALUES (?, ?, ?, ?)");
  q.bind(1, unix_now());
  q.bind(2, kind);
  q.bind(3, sample);
  q.bind(4, message);
  q.exec();
}

std::vector<EventRow> Store::events() const {
  std::vector<EventRow> rows;
  SQLite::Statement q(*m_db, "SELECT time, kind, sample, message FROM events ORDER BY id");
  while (q.executeStep())
    rows.push_back(
        {q.getColumn(0).getDouble(), q.getColumn(1).getString(), q.getColumn(2).getInt(), q.getColumn(3).getString()});
  return rows;
}

std::string Store::integrity_check() const {
  SQLite::Statement q(*m_db, "PRAGMA integrity_check");
  std::string result;
  while (q.executeStep()) {
    if (!result.empty()) result += '\n';
    result += q.getColumn(0).getString();
  }
  return result;
}

}  // namespace demsa::study
