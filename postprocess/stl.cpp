#include "postprocess/stl.hpp"

#include "postprocess/text.hpp"

#include <fmt/core.h>

#include <map>

namespace demsa::postprocess {

namespace {

/// The STL grammar as a small state machine over the lines' first words.
TriangleMesh parse(LineReader& in) {
  TriangleMesh mesh;
  std::map<std::array<double, 3>, std::size_t> index;  // bit-identical vertices become one point
  enum class Expect { solid, facet_or_end, outer_loop, vertex, endloop, endfacet, nothing };
  Expect expect = Expect::solid;
  std::array<std::size_t, 3> triangle{};
  int vertices = 0;
  std::string_view view;
  const auto fail = [&in](const std::string& message) { return ParseError(in.name(), in.line(), message); };
  while (in.next(view)) {
    const std::string line(view);
    const std::vector<std::string> words = split_words(line);
    if (words.empty()) continue;
    const std::string& key = words[0];
    switch (expect) {
      case Expect::solid:
        if (key != "solid") throw fail(fmt::format("expected 'solid NAME' (an ASCII STL), got {}", shown(line)));
        expect = Expect::facet_or_end;
        break;
      case Expect::facet_or_end:
        if (key == "endsolid") {
          expect = Expect::nothing;
        } else if (key == "facet" && words.size() == 5 && words[1] == "normal") {
          expect = Expect::outer_loop;
        } else {
          throw fail(fmt::format("expected 'facet normal nx ny nz' or 'endsolid', got {}", shown(line)));
        }
        break;
      case Expect::outer_loop:
        if (key != "outer" || words.size() != 2 || words[1] != "loop")
          throw fail(fmt::format("expected 'outer loop', got {}", shown(line)));
        expect = Expect::vertex;
        vertices = 0;
        break;
      case Expect::vertex: {
        if (key != "vertex" || words.size() != 4)
          throw fail(fmt::format("expected 'vertex x y z' (vertex {} of 3), got {}", vertices + 1, shown(line)));
        std::array<double, 3> p{};
        for (std::size_t d = 0; d < 3; ++d)
          if (!parse_double(words[d + 1], p[d], true))
            throw fail(fmt::format("vertex coordinate {} is not a finite number", shown(words[d + 1])));
        const auto [it, added] = index.try_emplace(p, mesh.points.size());
        if (added) mesh.points.push_back(p);
        triangle[static_cast<std::size_t>(vertices)] = it->second;
        if (++vertices == 3) expect = Expect::endloop;
        break;
      }
      case Expect::endloop:
        if (key != "endloop") throw fail(fmt::format("expected 'endloop' after three vertices, got {}", shown(line)));
        expect = Expect::endfacet;
        break;
      case Expect::endfacet:
        if (key != "endfacet") throw fail(fmt::format("expected 'endfacet', got {}", shown(line)));
        mesh.triangles.push_back(triangle);
        expect = Expect::facet_or_end;
        break;
      case Expect::nothing:
        throw fail(fmt::format("text after 'endsolid': {}", shown(line)));
    }
  }
  if (expect == Expect::solid) throw ParseError(in.name(), 0, "empty file: not an ASCII STL");
  if (expect != Expect::nothing)
    throw ParseError(in.name(), in.line(), "the file ends inside the solid (no 'endsolid'): cut short?");
  if (mesh.triangles.empty()) throw ParseError(in.name(), in.line(), "the solid has no facet");
  return mesh;
}

LineLimits line_limits(const StlLimits& limits) {
  LineLimits l;
  l.max_line_bytes = limits.max_line_bytes;
  l.max_bytes = limits.max_bytes;
  return l;
}

}  // namespace

TriangleMesh read_ascii_stl(const std::filesystem::path& path, const StlLimits& limits) {
  LineReader in(path, line_limits(limits));
  return parse(in);
}

TriangleMesh parse_ascii_stl(std::string_view text, const std::string& name, const StlLimits& limits) {
  LineReader in = LineReader::of_text(text, name, line_limits(limits));
  return parse(in);
}

}  // namespace demsa::postprocess
