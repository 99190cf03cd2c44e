// LIGGGHTS text dump reader: frames, column order, box flags, the last frame, and one test per malformed input.
#include "postprocess/dump.hpp"

#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <string>

namespace demsa::postprocess {
namespace {

using test::TempDir;
using test::write_file;

// Two frames of a `dump custom` file; the second has its columns in another order and no boundary flags.
const std::string k_two_frames =
    "ITEM: TIMESTEP\n"
    "100\n"
    "ITEM: NUMBER OF ATOMS\n"
    "3\n"
    "ITEM: BOX BOUNDS ff ff fm\n"
    "-0.15 0.15\n"
    "-0.15 0.15\n"
    "-0.01 0.2\n"
    "ITEM: ATOMS id type x y z radius \n"
    "3 1 0.1 0.2 0.3 0.002 \n"
    "1 1 -1e-3 2.5E-3 +4 0.001\n"
    "2 2 0 0 0 0.0035\n"
    "ITEM: TIMESTEP\n"
    "200\n"
    "ITEM: NUMBER OF ATOMS\n"
    "2\n"
    "ITEM: BOX BOUNDS\n"
    "0 1\n"
    "0 2\n"
    "0 3\n"
    "ITEM: ATOMS radius z y x type id vx\n"
    "0.5 3 2 1 1 7 9\n"
    "0.25 0.3 0.2 0.1 1 8 -9\n";

std::string frame_with_rows(const std::string& count, const std::string& columns, const std::string& rows) {
  return "ITEM: TIMESTEP\n5\nITEM: NUMBER OF ATOMS\n" + count + "\nITEM: BOX BOUNDS pp pp pp\n0 1\n0 1\n0 1\n" +
         "ITEM: ATOMS " + columns + "\n" + rows;
}

/// The message of the ParseError that reading all frames of `text` (as file `name`) throws; "" when none.
std::string error_of(const std::string& text, const std::string& name = "bad.dump",
                     std::vector<std::string> required = {}) {
  TempDir dir;
  write_file(dir / name, text);
  DumpReaderOptions options;
  options.required_columns = std::move(required);
  try {
    DumpReader reader(dir / name, options);
    DumpFrame frame;
    while (reader.next(frame)) {
    }
  } catch (const ParseError& e) {
    const std::string what = e.what();
    const std::string prefix = (dir / name).string();
    return what.rfind(prefix, 0) == 0 ? name + what.substr(prefix.size()) : what;
  }
  return "";
}

/// The message particles_from_frame raises on the first frame of `text` (read from memory as `name`); "" when it
/// raises none, "no frame" when the text holds no frame.
std::string particles_error_of(const std::string& text, const std::string& name) {
  DumpReader reader(text, name);
  DumpFrame f;
  if (!reader.next(f)) return "no frame";
  try {
    particles_from_frame(f);
  } catch (const ParseError& e) {
    return e.what();
  }
  return "";
}

/// What read_last_frame raises on `text` (in a file): the line it names (-1 when nothing is raised) and the message.
struct LastFrameError {
  long line = -1;
  std::string what;
};

LastFrameError last_frame_error_of(const std::string& text) {
  TempDir dir;
  write_file(dir / "t.dump", text);
  try {
    read_last_frame(dir / "t.dump");
  } catch (const ParseError& e) {
    return {e.line(), e.what()};
  }
  return {};
}

TEST(DumpReader, ReadsFramesAndColumnsInAnyOrder) {
  TempDir dir;
  write_file(dir / "a.dump", k_two_frames);
  DumpReader reader(dir / "a.dump");
  DumpFrame f;
  ASSERT_TRUE(reader.next(f));
  EXPECT_EQ(f.timestep, 100);
  EXPECT_EQ(f.atom_count, 3u);
  EXPECT_EQ(f.boundary, "ff ff fm");
  EXPECT_FALSE(f.triclinic);
  EXPECT_DOUBLE_EQ(f.box[0], -0.15);
  EXPECT_DOUBLE_EQ(f.box[5], 0.2);
  EXPECT_EQ(f.first_line, 1);
  EXPECT_EQ(f.atoms_line, 9);
  ASSERT_EQ(f.columns.size(), 6u);
  EXPECT_DOUBLE_EQ(f.column("x")[1], -1e-3);
  EXPECT_DOUBLE_EQ(f.column("y")[1], 2.5e-3);
  EXPECT_DOUBLE_EQ(f.column("z")[1], 4.0);
  EXPECT_DOUBLE_EQ(f.column("radius")[2], 0.0035);

  ASSERT_TRUE(reader.next(f));
  EXPECT_EQ(f.timestep, 200);
  EXPECT_EQ(f.boundary, "");
  EXPECT_EQ(f.first_line, 13);
  const Particles p = particles_from_frame(f);
  ASSERT_EQ(p.size(), 2u);
  EXPECT_EQ(p.id[0], 7);
  EXPECT_DOUBLE_EQ(p.x[0], 1.0);
  EXPECT_DOUBLE_EQ(p.y[0], 2.0);
  EXPECT_DOUBLE_EQ(p.z[0], 3.0);
  EXPECT_DOUBLE_EQ(p.radius[1], 0.25);
  EXPECT_FALSE(reader.next(f));
  EXPECT_EQ(reader.frames_read(), 2u);
  EXPECT_EQ(reader.bytes_read(), k_two_frames.size());
}

TEST(DumpReader, SmallBufferGivesTheSameFrames) {
  // Rows straddle many buffer refills.
  std::string rows;
  for (int i = 0; i < 2000; ++i) rows += std::to_string(i + 1) + " 1 " + std::to_string(i * 1e-4) + " 0.5 0.25 0.001\n";
  TempDir dir;
  write_file(dir / "big.dump", frame_with_rows("2000", "id type x y z radius", rows));
  DumpReaderOptions options;
  options.buffer_bytes = 4096;
  options.max_line_bytes = 256;
  DumpReader reader(dir / "big.dump", options);
  DumpFrame f;
  ASSERT_TRUE(reader.next(f));
  ASSERT_EQ(f.atom_count, 2000u);
  EXPECT_DOUBLE_EQ(f.column("id")[1999], 2000.0);
  EXPECT_DOUBLE_EQ(f.column("x")[1234], 1234 * 1e-4);
  EXPECT_FALSE(reader.next(f));
}

TEST(DumpReader, TriclinicBoxAndScaledCoordinates) {
  const std::string text =
      "ITEM: TIMESTEP\n1\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS xy xz yz pp pp ff\n0 2 0.1\n0 4 0\n0 8 0\n"
      "ITEM: ATOMS id type xs ys zs radius\n1 1 0.5 0.25 0.5 0.1\n";
  DumpReader reader(text, "tri.dump");
  DumpFrame f;
  ASSERT_TRUE(reader.next(f));
  EXPECT_TRUE(f.triclinic);
  EXPECT_EQ(f.boundary, "pp pp ff");
  EXPECT_DOUBLE_EQ(f.tilt[0], 0.1);
  EXPECT_THROW(particles_from_frame(f), ParseError);  // scaled coordinates need an orthogonal box

  const std::string ortho =
      "ITEM: TIMESTEP\n1\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS ff ff ff\n-1 1\n0 4\n0 8\n"
      "ITEM: ATOMS id type xs ys zs radius\n1 1 0.5 0.25 0.5 0.1\n";
  DumpReader r2(ortho, "ortho.dump");
  ASSERT_TRUE(r2.next(f));
  const Particles p = particles_from_frame(f);
  EXPECT_DOUBLE_EQ(p.x[0], 0.0);
  EXPECT_DOUBLE_EQ(p.y[0], 1.0);
  EXPECT_DOUBLE_EQ(p.z[0], 4.0);
}

TEST(DumpReader, LastFrameOfAMultiFrameFile) {
  TempDir dir;
  std::string text;
  for (int k = 0; k < 50; ++k)
    text += frame_with_rows("2", "id type x y z radius",
                            "1 1 " + std::to_string(k) + " 0 0 0.1\n2 1 0 " + std::to_string(2 * k) + " 0 0.1\n");
  write_file(dir / "traj.dump", text);
  const DumpFrame last = read_last_frame(dir / "traj.dump");
  EXPECT_DOUBLE_EQ(last.column("x")[0], 49.0);
  EXPECT_DOUBLE_EQ(last.column("y")[1], 98.0);
  EXPECT_EQ(last.first_line, 0);  // not counted on the fast path
  const DumpFrame first = read_first_frame(dir / "traj.dump");
  EXPECT_DOUBLE_EQ(first.column("x")[0], 0.0);
  EXPECT_EQ(first.first_line, 1);
}

TEST(DumpReader, LastFrameAcrossSearchBlocks) {
  // More than one backward search block (1 MiB) after the last marker, and markers before it.
  std::string rows;
  for (int i = 0; i < 40000; ++i) rows += std::to_string(i + 1) + " 1 0.123456789 0.5 0.25 0.001\n";
  std::string text = frame_with_rows("1", "id type x y z radius", "1 1 7 7 7 0.5\n") +
                     frame_with_rows("40000", "id type x y z radius", rows);
  TempDir dir;
  write_file(dir / "big.dump", text);
  const DumpFrame last = read_last_frame(dir / "big.dump");
  EXPECT_EQ(last.atom_count, 40000u);
  EXPECT_DOUBLE_EQ(last.column("id")[39999], 40000.0);
}

TEST(DumpReader, LastFrameErrorsNameTheAbsoluteLine) {
  const LastFrameError e =
      last_frame_error_of(frame_with_rows("1", "id type x y z radius", "1 1 0 0 0 0.1\n") +
                          frame_with_rows("2", "id type x y z radius", "1 1 0 0 0 0.1\n2 1 0 zz 0 0.1\n"));
  EXPECT_EQ(e.line, 21);
  EXPECT_NE(e.what.find("'zz' is not a finite number"), std::string::npos) << e.what;
}

TEST(DumpReader, ReadParticlesFiltersType) {
  TempDir dir;
  write_file(dir / "a.dump", k_two_frames.substr(0, k_two_frames.find("ITEM: TIMESTEP\n200")));
  const Particles all = read_particles(dir / "a.dump");
  EXPECT_EQ(all.size(), 3u);
  const Particles ones = read_particles(dir / "a.dump", 1);
  ASSERT_EQ(ones.size(), 2u);
  EXPECT_EQ(ones.id[0], 3);
  EXPECT_EQ(ones.id[1], 1);
}

TEST(DumpReader, ReadParticlesKeepsTheCallersOptions) {
  TempDir dir;
  write_file(dir / "a.dump", frame_with_rows("1", "id type x y z radius", "1 1 0 0 0 0.1"));  // no final '\n'
  EXPECT_THROW(read_particles(dir / "a.dump"), ParseError) << "a cut file is refused by default";
  DumpReaderOptions options;
  options.require_final_newline = false;
  EXPECT_EQ(read_particles(dir / "a.dump", 0, options).size(), 1u);
  options.require_final_newline = true;
  options.required_columns = {"vx"};
  EXPECT_EQ(test::message_of<ParseError>([&] { read_particles(dir / "a.dump", 0, options); }),
            (dir / "a.dump").string() + ":9: ITEM: ATOMS has no column 'vx' (columns: id type x y z radius)");
  options.required_columns = {"x"};
  EXPECT_EQ(test::message_of<ParseError>([&] { read_particles(dir / "a.dump", 0, options); }),
            (dir / "a.dump").string() +
                ":10: the file ends inside this line ('1 1 0 0 0 0.1', no end of line): cut "
                "short?");
  write_file(dir / "a.dump", frame_with_rows("1", "id type x y z", "1 1 0 0 0\n"));
  EXPECT_EQ(test::message_of<ParseError>([&] { read_particles(dir / "a.dump", 0, options); }),
            (dir / "a.dump").string() + ":9: ITEM: ATOMS has no column 'radius' (columns: id type x y z)")
      << "id type radius are still required";
}

// ---------------------------------------------------------------------------------------------- malformed input

TEST(DumpReaderErrors, EmptyFile) { EXPECT_EQ(error_of(""), "bad.dump: empty file: not a LIGGGHTS dump"); }

TEST(DumpReaderErrors, OnlyBlankLines) {
  EXPECT_EQ(error_of("\n\n  \n"), "bad.dump:3: no frame in the file (no 'ITEM: TIMESTEP' line)");
}

TEST(DumpReaderErrors, NotADump) {
  EXPECT_EQ(error_of("LIGGGHTS (Version 3.8.0)\n"),
            "bad.dump:1: expected 'ITEM: TIMESTEP', found 'LIGGGHTS (Version 3.8.0)': not a LIGGGHTS text dump");
}

TEST(DumpReaderErrors, TruncatedMidFrameRows) {
  const std::string text = frame_with_rows("4", "id type x y z radius", "1 1 0 0 0 0.1\n2 1 0 0 0 0.1\n");
  EXPECT_EQ(error_of(text),
            "bad.dump:12: file ends after 2 of the 4 atom rows announced for the frame whose ITEM: ATOMS is at line 9 "
            "(truncated?)");
}

TEST(DumpReaderErrors, TruncatedMidLine) {
  const std::string text = frame_with_rows("2", "id type x y z radius", "1 1 0 0 0 0.1\n2 1 0.5 0.");
  EXPECT_EQ(error_of(text), "bad.dump:11: the file ends inside this line ('2 1 0.5 0.', no end of line): cut short?");
  // A row cut short that still ends its line.
  EXPECT_EQ(error_of(text + "\n"), "bad.dump:11: atom row has 4 values, ITEM: ATOMS names 6 columns (line cut short?)");
}

TEST(DumpReaderErrors, TruncatedInHeader) {
  EXPECT_EQ(error_of("ITEM: TIMESTEP\n5\nITEM: NUMBER OF ATOMS\n"),
            "bad.dump:4: file ends inside the header of the frame starting at line 1 (expected the value of ITEM: "
            "NUMBER OF ATOMS); truncated?");
}

TEST(DumpReaderErrors, FewerRowsThanAtomCount) {
  const std::string text = frame_with_rows("3", "id type x y z radius", "1 1 0 0 0 0.1\n2 1 0 0 0 0.1\n") +
                           frame_with_rows("1", "id type x y z radius", "1 1 0 0 0 0.1\n");
  EXPECT_EQ(error_of(text), "bad.dump:12: only 2 atom rows before 'ITEM: TIMESTEP', but NUMBER OF ATOMS is 3");
}

TEST(DumpReaderErrors, MoreRowsThanAtomCount) {
  const std::string text = frame_with_rows("1", "id type x y z radius", "1 1 0 0 0 0.1\n2 1 0 0 0 0.1\n");
  EXPECT_EQ(error_of(text),
            "bad.dump:11: expected 'ITEM: TIMESTEP' after the 1 atom rows of the previous frame, found '2 1 0 0 0 "
            "0.1' (more rows than NUMBER OF ATOMS?)");
}

TEST(DumpReaderErrors, AtomCountBeyondTheFile) {
  // A count no file could hold is not allocated; the frame is reported as truncated.
  const std::string text = frame_with_rows("99999999999", "id type x y z radius", "1 1 0 0 0 0.1\n");
  EXPECT_EQ(error_of(text),
            "bad.dump:11: file ends after 1 of the 99999999999 atom rows announced for the frame whose ITEM: ATOMS is "
            "at line 9 (truncated?)");
}

TEST(DumpReaderErrors, NegativeAtomCount) {
  EXPECT_EQ(error_of(frame_with_rows("-2", "id", "")), "bad.dump:4: NUMBER OF ATOMS is -2: must not be negative");
}

TEST(DumpReaderErrors, NonIntegerTimestep) {
  EXPECT_EQ(error_of("ITEM: TIMESTEP\n12a\n"), "bad.dump:2: the value of ITEM: TIMESTEP is '12a', not an integer");
}

TEST(DumpReaderErrors, MissingColumn) {
  const std::string text = frame_with_rows("1", "id type x y z", "1 1 0 0 0\n");
  EXPECT_EQ(error_of(text, "bad.dump", {"id", "radius"}),
            "bad.dump:9: ITEM: ATOMS has no column 'radius' (columns: id type x y z)");
  // The same when the particles are asked for without required columns.
  EXPECT_EQ(particles_error_of(text, "mem.dump"),
            "mem.dump:9: ITEM: ATOMS has no column 'radius' (columns: id type x y z)");
}

TEST(DumpReaderErrors, DuplicateColumn) {
  EXPECT_EQ(error_of(frame_with_rows("1", "id x x", "1 0 0\n")), "bad.dump:9: ITEM: ATOMS names column 'x' twice");
}

TEST(DumpReaderErrors, NoColumns) {
  EXPECT_EQ(error_of(frame_with_rows("0", "", "")), "bad.dump:9: ITEM: ATOMS names no columns");
}

TEST(DumpReaderErrors, NonNumericField) {
  const std::string text = frame_with_rows("2", "id type x y z radius", "1 1 0 0 0 0.1\n2 1 0.5 abc 0 0.1\n");
  EXPECT_EQ(error_of(text), "bad.dump:11: column 'y': 'abc' is not a finite number");
}

TEST(DumpReaderErrors, NanField) {
  const std::string text = frame_with_rows("1", "id type x y z radius", "1 1 nan 0 0 0.1\n");
  EXPECT_EQ(error_of(text), "bad.dump:10: column 'x': 'nan' is not a finite number");
}

TEST(DumpReaderErrors, TooManyValues) {
  const std::string text = frame_with_rows("1", "id type x", "1 1 0 7\n");
  EXPECT_EQ(error_of(text), "bad.dump:10: atom row has more than the 3 values ITEM: ATOMS names");
}

TEST(DumpReaderErrors, BadBoxBounds) {
  EXPECT_EQ(error_of("ITEM: TIMESTEP\n1\nITEM: NUMBER OF ATOMS\n0\nITEM: BOX BOUNDS ff ff ff\n0 1\n0\n"),
            "bad.dump:7: box bound line has 1 values, expected 2: '0'");
  EXPECT_EQ(error_of("ITEM: TIMESTEP\n1\nITEM: NUMBER OF ATOMS\n0\nITEM: BOX BOUNDS ff ff ff\n0 1\n0 x\n"),
            "bad.dump:7: box bound 'x' is not a number");
}

TEST(DumpReaderErrors, NonIntegerId) {
  const std::string text = frame_with_rows("2", "id type x y z radius", "1 1 0 0 0 0.1\n2.5 1 0 0 0 0.1\n");
  EXPECT_EQ(particles_error_of(text, "ids.dump"), "ids.dump:11: id 2.5 is not an integer");
}

TEST(DumpReaderErrors, DuplicateIdNamesFileLineTimestepAndId) {
  // Every observable matches or counts atoms by id: a second row with one id is refused, not silently dropped.
  const std::string text =
      frame_with_rows("3", "id type x y z radius", "4 1 0 0 0 0.1\n7 1 1 0 0 0.1\n4 1 2 0 0 0.1\n");
  EXPECT_EQ(particles_error_of(text, "dup.dump"),
            "dup.dump:12: atom id 4 appears twice in the frame of time step 5 (lines 10 and 12)");
  TempDir dir;
  write_file(dir / "dup.dump", text);
  EXPECT_EQ(test::message_of<ParseError>([&] { read_particles(dir / "dup.dump"); }),
            (dir / "dup.dump").string() + ":12: atom id 4 appears twice in the frame of time step 5 (lines 10 and 12)");
}

TEST(DumpReaderErrors, MoreRowsInTheLastFrameNamesItsRowCount) {
  // read_last_frame reads the frame after the last one into a fresh frame: the message still counts the rows of
  // the frame before it.
  const std::string text = frame_with_rows("2", "id type x y z radius", "1 1 0 0 0 0.1\n2 1 0 0 0 0.1\n") +
                           frame_with_rows("1", "id type x y z radius", "1 1 0 0 0 0.1\n2 1 0 0 0 0.1\n");
  const LastFrameError e = last_frame_error_of(text);
  EXPECT_EQ(e.line, 22);
  EXPECT_NE(e.what.find("after the 1 atom rows of the previous frame"), std::string::npos) << e.what;
}

TEST(DumpReaderErrors, BinaryGarbage) {
  std::string garbage;
  unsigned state = 12345;
  for (int i = 0; i < 100000; ++i) {
    state = state * 1103515245u + 12345u;
    garbage.push_back(static_cast<char>((state >> 16) & 0xff));
  }
  const std::string e = error_of(garbage);
  EXPECT_EQ(e.rfind("bad.dump:", 0), 0u) << e;
  EXPECT_NE(e.find("not a LIGGGHTS text dump"), std::string::npos) << e;
  // Garbage after a valid header: named as the bad row.
  const std::string mixed = frame_with_rows("1", "id type x y z radius", garbage);
  const std::string e2 = error_of(mixed);
  EXPECT_EQ(e2.rfind("bad.dump:10: ", 0), 0u) << e2;
}

TEST(DumpReaderErrors, LineLongerThanTheLimit) {
  DumpReaderOptions options;
  options.max_line_bytes = 256;
  DumpReader reader(std::string(1000, 'a'), "long.dump", options);
  DumpFrame f;
  EXPECT_EQ(test::message_of<ParseError>([&] { reader.next(f); }),
            "long.dump:1: line longer than 256 bytes: not a LIGGGHTS text dump (binary data?)");
}

TEST(DumpReaderErrors, MissingFileAndDirectory) {
  TempDir dir;
  EXPECT_THROW(DumpReader(dir / "nope.dump"), ParseError);
  EXPECT_THROW(DumpReader(dir.path()), ParseError);
  EXPECT_THROW(read_last_frame(dir / "nope.dump"), ParseError);
}

TEST(DumpReaderErrors, LastFrameTruncated) {
  const LastFrameError e = last_frame_error_of(frame_with_rows("1", "id type x y z radius", "1 1 0 0 0 0.1\n") +
                                               frame_with_rows("3", "id type x y z radius", "1 1 0 0 0 0.1\n"));
  EXPECT_EQ(e.line, 21);
  EXPECT_NE(e.what.find("file ends after 1 of the 3 atom rows"), std::string::npos) << e.what;
}

TEST(DumpReaderOptionsTest, ValidateNamesFieldAndValue) {
  DumpReaderOptions o;
  o.buffer_bytes = 10;
  EXPECT_EQ(test::message_of<std::invalid_argument>([&] { o.validate(); }),
            "DumpReaderOptions.buffer_bytes = 10: must be at least 4096");
}

TEST(DumpReaderErrors, FinalNewlineRequiredByDefault) {
  // A cut inside the last value of the last row leaves a row that parses: only the missing end of line tells.
  const std::string cut = frame_with_rows("2", "id type x y z radius", "1 1 0 0 0 0.1\n2 1 0 0 0 0.12");
  TempDir dir;
  write_file(dir / "c.dump", cut);
  DumpReaderOptions lenient;
  lenient.require_final_newline = false;
  EXPECT_NO_THROW(read_last_frame(dir / "c.dump", lenient));
  DumpReaderOptions options;  // the default: the cut row was read as complete before
  EXPECT_EQ(test::message_of<ParseError>([&] { read_last_frame(dir / "c.dump", options); }),
            (dir / "c.dump").string() +
                ":11: the file ends inside this line ('2 1 0 0 0 0.12', no end of line): "
                "cut short?");
  write_file(dir / "c.dump", cut + "\n");
  EXPECT_EQ(read_last_frame(dir / "c.dump", options).atom_count, 2u);
  // In memory as well.
  DumpReader reader(cut, "mem.dump", options);
  DumpFrame frame;
  EXPECT_EQ(test::message_of<ParseError>([&] { reader.next(frame); }),
            "mem.dump:11: the file ends inside this line ('2 1 0 0 0 0.12', no end of line): cut short?");
}

TEST(DumpReaderErrors, ShortFrameSaysHowManyRows) {
  TempDir dir;
  write_file(dir / "s.dump", frame_with_rows("4", "id type x y z radius", "1 1 0 0 0 0.1\n2 1 0 0 0 0.1\n"));
  try {
    read_last_frame(dir / "s.dump");
    FAIL() << "no exception";
  } catch (const ShortFrameError& e) {
    EXPECT_EQ(e.rows(), 2u);
    EXPECT_EQ(e.announced(), 4u);
    EXPECT_EQ(e.line(), 12);
    EXPECT_EQ(e.message(),
              "file ends after 2 of the 4 atom rows announced for the frame whose ITEM: ATOMS is at line 9 "
              "(truncated?)");
  }
  write_file(dir / "s.dump", frame_with_rows("3", "id type x y z radius", "1 1 0 0 0 0.1\n") +
                                 frame_with_rows("1", "id type x y z radius", "1 1 0 0 0 0.1\n"));
  try {
    DumpReader reader(dir / "s.dump");
    DumpFrame frame;
    reader.next(frame);
    FAIL() << "no exception";
  } catch (const ShortFrameError& e) {
    EXPECT_EQ(e.rows(), 1u);
    EXPECT_EQ(e.announced(), 3u);
  }
  // More rows than announced is not a short frame.
  write_file(dir / "s.dump", frame_with_rows("1", "id type x y z radius", "1 1 0 0 0 0.1\n2 1 0 0 0 0.1\n"));
  EXPECT_THROW(
      {
        try {
          read_last_frame(dir / "s.dump");
        } catch (const ShortFrameError&) {
          FAIL() << "a ShortFrameError";
        }
      },
      ParseError);
}

}  // namespace
}  // namespace demsa::postprocess
