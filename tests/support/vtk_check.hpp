#pragma once
// Checks of the ParaView files of a case (exec/case_vtk.hpp) read back with VTK's own XML reader: Debian's
// python3-vtk9 through tests/data/vtk/read_vtp.py. Header-only: the test modules that use it link postprocess.
#include "postprocess/dump.hpp"
#include "postprocess/oedometer.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

namespace demsa::test {

/// What read_vtp.py prints for `files`, keyed by path: points, verts, polys, bounds, coordinates, arrays (type,
/// components, values), polygon_sizes. A failed read is a test failure (and an empty object).
inline nlohmann::json read_vtp(const std::vector<std::filesystem::path>& files) {
  // Debian's python3 (where python3-vtk9 installs), whatever python3 comes first on PATH.
  std::vector<std::string> argv{"/usr/bin/python3", data_path("vtk/read_vtp.py").string()};
  for (const std::filesystem::path& f : files) argv.push_back(f.string());
  const CommandResult r = run_command(argv);
  if (r.exit_code != 0) {
    ADD_FAILURE() << "VTK's reader failed (python3-vtk9 missing? scripts/install-deps.sh installs it):\n"
                  << r.out << r.err;
    return nlohmann::json::object();
  }
  return nlohmann::json::parse(r.out);
}

/// The particles file holds every atom of `frame`, row by row: position, id, type, radius and velocity.
inline void expect_particles_match(const nlohmann::json& p, const postprocess::DumpFrame& frame) {
  const std::size_t n = frame.atom_count;
  ASSERT_EQ(p.at("points").get<std::size_t>(), n);
  EXPECT_EQ(p.at("verts").get<std::size_t>(), n);
  EXPECT_EQ(p.at("polys").get<std::size_t>(), 0u);
  const nlohmann::json& a = p.at("arrays");
  for (const char* name : {"id", "type", "radius", "velocity"}) ASSERT_TRUE(a.contains(name)) << name;
  ASSERT_EQ(a.at("velocity").at("components").get<int>(), 3);
  const auto column = [&](const char* name) { return frame.column(name); };
  for (std::size_t i = 0; i < n; ++i) {
    SCOPED_TRACE(i);
    EXPECT_EQ(a.at("id").at("values")[i].get<double>(), column("id")[i]);
    EXPECT_EQ(a.at("type").at("values")[i].get<double>(), column("type")[i]);
    EXPECT_EQ(a.at("radius").at("values")[i].get<double>(), column("radius")[i]);
    const char* v[3] = {"vx", "vy", "vz"};
    const char* x[3] = {"x", "y", "z"};
    for (std::size_t d = 0; d < 3; ++d) {
      EXPECT_EQ(a.at("velocity").at("values")[3 * i + d].get<double>(), column(v[d])[i]);
      EXPECT_EQ(p.at("coordinates")[i][d].get<double>(), column(x[d])[i]);
    }
  }
  if (n > 0) {
    const std::vector<double> radii = a.at("radius").at("values").get<std::vector<double>>();
    const auto r = column("radius");
    EXPECT_EQ(*std::min_element(radii.begin(), radii.end()), *std::min_element(r.begin(), r.end()));
    EXPECT_EQ(*std::max_element(radii.begin(), radii.end()), *std::max_element(r.begin(), r.end()));
  }
}

inline nlohmann::json case_json(const std::filesystem::path& dir) {
  return nlohmann::json::parse(read_file(dir / "case.json"));
}

/// pedestal.vtp: one triangle per facet of the case's pedestal.stl, within the pedestal of case.json.
inline void expect_pedestal_matches(const nlohmann::json& s, const std::filesystem::path& dir) {
  const std::string stl = read_file(dir / "pedestal.stl");
  std::size_t facets = 0;
  for (std::size_t at = stl.find("facet normal"); at != std::string::npos; at = stl.find("facet normal", at + 1))
    ++facets;
  ASSERT_GT(facets, 10u);
  EXPECT_EQ(s.at("polys").get<std::size_t>(), facets);
  const std::vector<int> sizes = s.at("polygon_sizes").get<std::vector<int>>();
  EXPECT_TRUE(std::all_of(sizes.begin(), sizes.end(), [](int k) { return k == 3; }));
  const double r = case_json(dir).at("pile").at("pedestal_radius_m").get<double>();
  const double h = case_json(dir).at("pile").at("pedestal_height_m").get<double>();
  const nlohmann::json& b = s.at("bounds");
  // The rim is a polygon: its extent lies between r cos(pi/segments) and r (1 % covers rings of 5 mm on 35 mm).
  for (int d = 0; d < 4; ++d) {
    EXPECT_LE(std::abs(b[d].get<double>()), r * (1 + 1e-12)) << d;
    EXPECT_GE(std::abs(b[d].get<double>()), 0.99 * r) << d;
  }
  EXPECT_NEAR(b[4].get<double>(), 0.0, 1e-12);
  EXPECT_NEAR(b[5].get<double>(), h, 1e-12);
}

/// box.vtp: floor and four walls of case.json's box; plate.vtp: two triangles over the box at the last plate height
/// of plate_states.txt.
inline void expect_oedometer_geometry_matches(const nlohmann::json& box, const nlohmann::json& plate,
                                              const std::filesystem::path& dir) {
  const nlohmann::json doc = case_json(dir);
  const double side = doc.at("oedometer").at("box_side_m").get<double>();
  const double height = doc.at("oedometer").at("box_height_m").get<double>();
  EXPECT_EQ(box.at("polys").get<int>(), 5);
  EXPECT_EQ(box.at("points").get<int>(), 8);
  EXPECT_EQ(box.at("polygon_sizes"), nlohmann::json::array({4, 4, 4, 4, 4}));
  const std::vector<double> expected{-side / 2, side / 2, -side / 2, side / 2, 0.0, height};
  for (std::size_t d = 0; d < 6; ++d) EXPECT_DOUBLE_EQ(box.at("bounds")[d].get<double>(), expected[d]) << d;
  const std::vector<postprocess::PlateState> states = postprocess::read_plate_states(dir / "plate_states.txt");
  ASSERT_FALSE(states.empty());
  EXPECT_EQ(plate.at("polys").get<int>(), 2);
  for (std::size_t d = 0; d < 4; ++d) EXPECT_DOUBLE_EQ(plate.at("bounds")[d].get<double>(), expected[d]) << d;
  EXPECT_DOUBLE_EQ(plate.at("bounds")[4].get<double>(), states.back().plate_z_m);
  EXPECT_DOUBLE_EQ(plate.at("bounds")[5].get<double>(), states.back().plate_z_m);
}

}  // namespace demsa::test
