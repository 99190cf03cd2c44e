// The ASCII STL reader (the meshes of a case) and the VTK PolyData text of surfaces and particles. That VTK itself
// reads these files is tested in tests/integration/test_cli_export_vtk.cpp.
#include "postprocess/stl.hpp"
#include "postprocess/vtk.hpp"

#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <string>

namespace demsa::postprocess {
namespace {

using test::message_of;

// Two triangles of a unit square sharing the diagonal's vertices (written as demsa's plate.stl is).
const std::string k_square =
    "solid plate\n"
    " facet normal 0.000000e+00 0.000000e+00 1.000000e+00\n"
    "  outer loop\n"
    "   vertex -5.000000000e-01 -5.000000000e-01 0.000000000e+00\n"
    "   vertex 5.000000000e-01 -5.000000000e-01 0.000000000e+00\n"
    "   vertex 5.000000000e-01 5.000000000e-01 0.000000000e+00\n"
    "  endloop\n"
    " endfacet\n"
    " facet normal 0.000000e+00 0.000000e+00 1.000000e+00\n"
    "  outer loop\n"
    "   vertex -5.000000000e-01 -5.000000000e-01 0.000000000e+00\n"
    "   vertex 5.000000000e-01 5.000000000e-01 0.000000000e+00\n"
    "   vertex -5.000000000e-01 5.000000000e-01 0.000000000e+00\n"
    "  endloop\n"
    " endfacet\n"
    "endsolid plate\n";

TEST(Stl, SharedVerticesBecomeOnePoint) {
  const TriangleMesh mesh = parse_ascii_stl(k_square, "plate.stl");
  ASSERT_EQ(mesh.points.size(), 4u);
  ASSERT_EQ(mesh.triangles.size(), 2u);
  EXPECT_EQ(mesh.triangles[0], (std::array<std::size_t, 3>{0, 1, 2}));
  EXPECT_EQ(mesh.triangles[1], (std::array<std::size_t, 3>{0, 2, 3}));
  EXPECT_EQ(mesh.points[3], (std::array<double, 3>{-0.5, 0.5, 0.0}));
}

std::string replaced(const std::string& from, const std::string& to, std::size_t nth = 0) {
  std::string text = k_square;
  std::size_t at = text.find(from);
  for (std::size_t k = 0; k < nth; ++k) at = text.find(from, at + 1);
  text.replace(at, from.size(), to);
  return text;
}

TEST(Stl, MalformedFilesNameTheLineAndTheValue) {
  const auto error = [](const std::string& text) {
    return message_of<ParseError>([&] { parse_ascii_stl(text, "m.stl"); });
  };
  EXPECT_NE(error(replaced("-5.000000000e-01", "-5.0e-0l", 2)).find("m.stl:5: vertex coordinate '-5.0e-0l'"),
            std::string::npos);
  EXPECT_NE(error(replaced("0.000000000e+00", "nan", 2)).find("m.stl:6:"), std::string::npos);
  EXPECT_NE(error(replaced("  endloop\n", "", 0)).find("m.stl:7: expected 'endloop'"), std::string::npos);
  EXPECT_NE(error(replaced("solid plate", "sold plate")).find("m.stl:1: expected 'solid NAME'"), std::string::npos);
  EXPECT_NE(error(k_square.substr(0, k_square.find(" facet normal", 10))).find("no 'endsolid'"), std::string::npos);
  EXPECT_NE(error("solid empty\nendsolid empty\n").find("m.stl:2: the solid has no facet"), std::string::npos);
  EXPECT_NE(error("").find("m.stl: empty file"), std::string::npos);
  EXPECT_NE(error(k_square + "solid again\n").find("m.stl:17: text after 'endsolid'"), std::string::npos);
  // Binary STL: an 80-byte header, then raw floats: never a line of STL keywords.
  std::string binary(80, ' ');
  binary.replace(0, 5, "solid");
  binary += std::string("\x02\x00\x00\x00\x00\x00\x80\x3f", 8);
  EXPECT_NE(error(binary).find("m.stl:1:"), std::string::npos) << error(binary);
  EXPECT_NE(error(std::string(5000, 'x')).find("m.stl"), std::string::npos);
}

TEST(Vtk, SurfaceTextHasItsPolygonsWithEndOffsets) {
  Surface s;
  s.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0.25}, {0, 1, 0}};
  s.polygons = {{0, 1, 2}, {0, 2, 3, 1}};
  const std::string text = surface_vtp(s);
  EXPECT_NE(text.find("NumberOfPoints=\"4\""), std::string::npos);
  EXPECT_NE(text.find("NumberOfPolys=\"2\""), std::string::npos);
  EXPECT_NE(text.find("          1 1 0.25\n"), std::string::npos) << text;
  EXPECT_NE(text.find("Name=\"connectivity\" format=\"ascii\">\n          0 1 2\n          0 2 3 1\n"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("Name=\"offsets\" format=\"ascii\">\n          3\n          7\n"), std::string::npos) << text;
}

TEST(Vtk, ParticlesNeedAllThreeVelocityComponentsOrNone) {
  const std::string head = "ITEM: TIMESTEP\n5\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS ff ff ff\n0 1\n0 1\n0 1\n";
  DumpFrame frame;
  DumpReader(head + "ITEM: ATOMS id type x y z radius vx vz\n4 1 0.5 0.5 0.5 0.1 1 2\n", "two.dump").next(frame);
  EXPECT_NE(message_of<ParseError>([&] {
              particles_vtp(frame);
            }).find("two.dump:9: ITEM: ATOMS of time step 5 has vx vz but not all of vx vy vz"),
            std::string::npos);
  DumpReader(head + "ITEM: ATOMS id type x y z radius\n4 1 0.5 0.5 0.5 0.1\n", "none.dump").next(frame);
  const std::string text = particles_vtp(frame);
  EXPECT_EQ(text.find("velocity"), std::string::npos);
  EXPECT_NE(text.find("Name=\"id\" format=\"ascii\">\n          4\n"), std::string::npos) << text;
}

}  // namespace
}  // namespace demsa::postprocess
