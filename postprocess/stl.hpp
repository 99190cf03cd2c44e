#pragma once
// Reading ASCII STL, the mesh format LIGGGHTS's `fix mesh/surface file` reads (demsa writes the pile's pedestal and
// the oedometer's plate in it, orchestrator/cases/geometry.hpp):
//   solid NAME / facet normal nx ny nz / outer loop / vertex x y z (three times) / endloop / endfacet / ... /
//   endsolid NAME
// The normals are not kept (the vertex order gives the orientation). Binary STL is refused.
#include "postprocess/error.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace demsa::postprocess {

/// A triangle mesh with shared vertices: vertices that are bit-identical in the file are one point.
struct TriangleMesh {
  std::vector<std::array<double, 3>> points;
  std::vector<std::array<std::size_t, 3>> triangles;  ///< indices into points, in the file's vertex order
};

/// Limits of the reader: an STL beyond them is not one demsa or a user would hand to a case.
struct StlLimits {
  std::size_t max_line_bytes = std::size_t{1} << 12;   ///< longest line [bytes]
  std::uint64_t max_bytes = std::uint64_t{256} << 20;  ///< largest file [bytes]
};

/// Reads an ASCII STL. Throws ParseError naming the file, the line and the value on anything that is not one: a
/// missing `solid` line, a keyword out of order, a facet without three vertices, a non-finite or non-numeric
/// coordinate, a missing `endsolid`, binary data, a file without any facet, or a file or line beyond `limits`.
TriangleMesh read_ascii_stl(const std::filesystem::path& path, const StlLimits& limits = {});
/// The same from text held in memory; `name` stands for the file in messages.
TriangleMesh parse_ascii_stl(std::string_view text, const std::string& name, const StlLimits& limits = {});

}  // namespace demsa::postprocess
