// The readers of user files through the real binary: /dev/zero and endless lines end in exit 2 naming the file,
// plate files with impossible rows, CSVs with a byte-order mark, without a header or with a constant design
// column, and dumps with a duplicated atom id (postprocess and compare agree).
#include "orchestrator/util/csv.hpp"
#include "support/test_support.hpp"

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/stat.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <string>

namespace demsa::test {
namespace {

namespace fs = std::filesystem;

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(CliReaders, DevZeroIsRefusedQuicklyByEveryReader) {
  // Before: the plate reader grew to 23 GB and `sensitivity --data` ended in a bare std::bad_alloc.
  const auto start = std::chrono::steady_clock::now();
  CommandResult r = run_demsa({"postprocess", "oedometer", "/dev/zero"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  // Refused before it is opened: a device is not a plate file (issue 45: a FIFO would block the read for ever).
  EXPECT_TRUE(has(r.err, "/dev/zero: a character device, not a regular file")) << r.err;
  r = run_demsa({"sensitivity", "--data", "/dev/zero", "--inputs", "a,b", "--response", "y"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(has(r.err, "/dev/zero:1: line longer than 1048576 bytes: not a CSV table")) << r.err;
  r = run_demsa({"sensitivity", "--saltelli", "/dev/zero", "--responses", "/dev/zero"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(has(r.err, "/dev/zero:1: line longer")) << r.err;
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(60));
}

TEST(CliReaders, AFifoWhereDemsaReadsIsRefusedNotWaitedOn) {
  // issue 45: a FIFO as the study file, its store, a case.json, a dump or the rate cache blocked demsa in open(2)
  // for ever. Each is refused before it is opened (exit 2, naming the file); `timeout` ends a read that blocks.
  TempDir dir;
  const auto fifo = [&](const fs::path& path) {
    fs::create_directories(path.parent_path());
    fs::remove(path);
    ASSERT_EQ(::mkfifo(path.c_str(), 0600), 0) << path;
  };
  const auto refused = [&](const std::vector<std::string>& args, const fs::path& file, const std::string& env = "") {
    std::vector<std::string> all{"timeout", "30", "env"};
    if (!env.empty()) all.push_back(env);
    all.push_back(DEMSA_BINARY);
    all.insert(all.end(), args.begin(), args.end());
    const CommandResult r = run_command(all);
    EXPECT_EQ(r.exit_code, 2) << args[0] << ": " << r.err;
    EXPECT_TRUE(has(r.err, file.string() + ": a FIFO, not a regular file")) << r.err;
  };
  fifo(dir / "study.toml");
  refused({"run", (dir / "study.toml").string(), "--dir", (dir / "s").string()}, dir / "study.toml");
  fifo(dir / "case" / "case.json");
  refused({"measure", (dir / "case").string()}, dir / "case" / "case.json");
  fifo(dir / "pile.dump");
  refused({"postprocess", "pile", (dir / "pile.dump").string()}, dir / "pile.dump");
  // A study whose store is a FIFO.
  write_file(dir / "real.toml", StudyToml{.name = "fifo", .samples = 2}.text());
  fs::create_directories(dir / "st");
  fs::copy_file(dir / "real.toml", dir / "st" / "study.toml");
  fifo(dir / "st" / "study.db");
  refused({"status", (dir / "st").string()}, dir / "st" / "study.db");
  // The rate cache of the dry run.
  fifo(dir / "rates.json");
  write_file(dir / "dry.toml", StudyToml{.name = "dry", .samples = 2, .run = fake_liggghts_run_lines()}.text());
  refused({"run", (dir / "dry.toml").string(), "--dir", (dir / "dry").string(), "--dry-run"}, dir / "rates.json",
          "DEMSA_RATE_CACHE=" + (dir / "rates.json").string());
}

TEST(CliReaders, PlateFileWithALongLineOrDecreasingLoads) {
  TempDir dir;
  write_file(dir / "plate_states.txt",
             "# load_N plate_z_m force_N converged\n100 0.06 100 1\n" + std::string(200000, '1') + "\n");
  CommandResult r = run_demsa({"postprocess", "oedometer", (dir / "plate_states.txt").string()});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(has(r.err, "plate_states.txt:3: line longer than 65536 bytes")) << r.err;
  write_file(dir / "plate_states.txt", "# load_N plate_z_m force_N converged\n400 0.06 400 1\n100 0.07 100 1\n");
  r = run_demsa({"postprocess", "oedometer", (dir / "plate_states.txt").string()});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(has(r.err, "plate_states.txt:3: column 'load_N': 100 is below the 400 of line 2")) << r.err;
  write_file(dir / "plate_states.txt", "# load_N plate_z_m force_N converged\n100 1e308 100 1\n");
  r = run_demsa({"postprocess", "oedometer", (dir / "plate_states.txt").string()});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(has(r.err, "plate_states.txt:2: column 'plate_z_m': 1e+308 m is not a plate position")) << r.err;
}

/// y = 3a + b² on a small grid-free design.
std::string data_csv(const std::string& header) {
  std::string text = header;
  for (int i = 0; i < 40; ++i) {
    const double a = std::fmod(0.618034 * i, 1.0), b = std::fmod(0.7548777 * i + 0.1, 1.0);
    text += fmt::format("{},{},{}\n", a, b, 3 * a + b * b);
  }
  return text;
}

TEST(CliReaders, CsvWithAByteOrderMark) {
  TempDir dir;
  write_file(dir / "data.csv", "\xEF\xBB\xBF" + data_csv("a,b,y\n"));
  const CommandResult r =
      run_demsa({"sensitivity", "--data", (dir / "data.csv").string(), "--inputs", "a,b", "--response", "y",
                 "--metamodels", "rsm2", "--bootstrap", "0", "--json", (dir / "out.json").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(read_file(dir / "out.json"));
  EXPECT_EQ(j["inputs"][0], "a");
}

TEST(CliReaders, SaltelliDesignWithAConstantColumnAndResponsesWithoutHeader) {
  TempDir dir;
  ASSERT_EQ(run_demsa({"design", "saltelli", "-N", "16", "--dim", "3", "-o", (dir / "d.csv").string()}).exit_code, 0);
  const util::CsvTable design = util::read_csv(dir / "d.csv");
  std::string y = "y\n", bare;
  for (int i = 0; i < design.rows(); ++i) {
    const std::string row = fmt::format("{}\n", design.values(i, 1) + 2 * design.values(i, 2));
    y += row;
    bare += row;
  }
  write_file(dir / "y.csv", y);
  ASSERT_EQ(run_demsa({"sensitivity", "--saltelli", (dir / "d.csv").string(), "--responses", (dir / "y.csv").string(),
                       "--bootstrap", "0"})
                .exit_code,
            0);
  // The third parameter held at one value: the design does not sample it.
  std::string constant = "block," + design.columns[1] + "," + design.columns[2] + "," + design.columns[3] + "\n";
  for (int i = 0; i < design.rows(); ++i)
    constant += fmt::format("{},{},{},0.5\n", design.values(i, 0), design.values(i, 1), design.values(i, 2));
  write_file(dir / "c.csv", constant);
  CommandResult r = run_demsa({"sensitivity", "--saltelli", (dir / "c.csv").string(), "--responses",
                               (dir / "y.csv").string(), "--bootstrap", "0"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(has(r.err, fmt::format("c.csv:1: column '{}' holds 0.5 on every one of its {} rows", design.columns[3],
                                     design.rows())))
      << r.err;
  // Responses without their header line: said so, not "N-1 rows, but the design has N".
  write_file(dir / "bare.csv", bare);
  r = run_demsa({"sensitivity", "--saltelli", (dir / "d.csv").string(), "--responses", (dir / "bare.csv").string()});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(has(r.err, "bare.csv:1: the first row holds numbers")) << r.err;
  EXPECT_TRUE(has(r.err, "the file has no header row")) << r.err;
}

std::string dump_with_ids(const std::string& ids_and_rows) {
  return "ITEM: TIMESTEP\n42\nITEM: NUMBER OF ATOMS\n3\nITEM: BOX BOUNDS ff ff ff\n-1 1\n-1 1\n-1 1\n"
         "ITEM: ATOMS id type x y z radius\n" +
         ids_and_rows;
}

TEST(CliReaders, DuplicatedAtomIdRefusedByPostprocessAndCompare) {
  TempDir dir;
  write_file(dir / "ok.dump", dump_with_ids("1 1 0 0 0.01 0.001\n2 1 0.1 0 0.01 0.001\n3 1 0.2 0 0.01 0.001\n"));
  write_file(dir / "dup.dump", dump_with_ids("1 1 0 0 0.01 0.001\n2 1 0.1 0 0.01 0.001\n2 1 0.2 0 0.01 0.001\n"));
  const std::string expected =
      (dir / "dup.dump").string() + ":12: atom id 2 appears twice in the frame of time step 42 (lines 11 and 12)";
  CommandResult r = run_demsa({"postprocess", "pile", (dir / "dup.dump").string()});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(has(r.err, expected)) << r.err;
  r = run_demsa({"compare", (dir / "ok.dump").string(), (dir / "dup.dump").string()});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(has(r.err, expected)) << r.err;
}

TEST(CliReaders, CompareErrorsNameTheFile) {
  // A pile measure that fails (no particle on the pedestal) says which of the two dumps it failed on.
  TempDir dir;
  write_file(dir / "a.dump", dump_with_ids("1 1 0 0 0.01 0.001\n2 1 0.1 0 0.01 0.001\n3 1 0.2 0 0.01 0.001\n"));
  write_file(dir / "b.dump", dump_with_ids("1 1 0 0 0.01 0.001\n2 1 0.1 0 0.01 0.001\n3 1 0.2 0 0.01 0.001\n"));
  const CommandResult r =
      run_demsa({"compare", (dir / "a.dump").string(), (dir / "b.dump").string(), "--pile", "--pedestal-top", "0.5"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(has(r.err, (dir / "a.dump").string() + ": ")) << r.err;
}

}  // namespace
}  // namespace demsa::test
