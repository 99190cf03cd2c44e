#pragma once
// The rotating drum (GranuDrum-like testers): a horizontal cylinder partly filled with the material turns at a
// constant speed; a camera looks through its end plate, and the time-averaged side view gives the free surface, whose
// dynamic angle, shape and fill a calibration compares with laboratory photographs. Its settings ([drum]), case, the
// measurement of a case and of a photograph (postprocess/drum.hpp measures both alike) and report.
//
// Frames: the drum's axis is LIGGGHTS's y, gravity −z, the drum's centre at x = z = 0, its end plates at y = 0 and
// y = depth. The camera looks through the end plate at y = 0 (along +y), so the picture's x is LIGGGHTS x and the
// picture's up is LIGGGHTS z; case.json records this mapping. A turn about +y by the right-hand rule carries +z
// towards +x: clockwise as the camera sees it.
#include "orchestrator/experiments/experiment.hpp"
#include "orchestrator/experiments/geometry.hpp"
#include "postprocess/drum.hpp"

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace demsa::experiments::drum {

/// [drum]. Defaults: the GranuDrum (radius 42 mm, depth 20 mm) with 50 mL of a powder of about 1.2 mm particles.
struct DrumSettings {
  std::string preset;                                                         ///< "" or "granudrum"
  double radius = 0.042;                                                      ///< inner radius R [m]
  double depth = 0.020;                                                       ///< between the end plates [m]
  double rpm = 15.0;                                                          ///< turns per minute
  postprocess::DrumRotation rotation = postprocess::DrumRotation::clockwise;  ///< as the camera sees it
  double bulk_volume = 5e-5;      ///< the fill's bulk volume [m³] (the lab's 50 mL)
  long particles = 0;             ///< the full-size count instead of bulk_volume (0: from bulk_volume)
  double packing_fraction = 0.6;  ///< solid fraction of the settled bed: bulk_volume → count
  std::vector<double> diameters;  ///< size classes [m] (empty: the truncated normal `radii`)
  std::vector<double> fractions;  ///< their number fractions (renormalised to sum 1)
  study::RadiusDistribution radii{0.525e-3, 0.75e-3, 0.6e-3, 0.05e-3};  ///< without classes
  double coarse_grain = 1.0;                                            ///< K: radii × K, count / K³
  int wall_sides = 48;              ///< sides of the polygon of the drum's wall mesh
  double settle_time = 0.3;         ///< the fill settles in the drum at rest [s]
  double spin_up = 1.5;             ///< the drum turns this long before the first snapshot [s]
  double window = 2.0;              ///< snapshots are taken over this time [s]
  double snapshot_interval = 0.04;  ///< one snapshot every this much time [s]
  int image_size = 406;             ///< side of the occupancy image [px] (the lab's images: 406)
  double judged_radius = 0.77;      ///< postprocess::DrumSurfaceOptions::judged_radius
  double angle_half_width = 0.5;    ///< postprocess::DrumSurfaceOptions::angle_half_width
  /// Fractions of R: within ±0.45 R, where the 45 rpm GranuDrum photograph's surface still lies inside the judged
  /// circle (at −0.6 R a 40° surface already leaves it).
  std::vector<double> stations = {-0.45, -0.3, -0.15, 0.0, 0.15, 0.3, 0.45};
  double threshold = 0.5;  ///< postprocess::DrumSurfaceOptions::threshold
};

/// The most snapshots a case's window may hold (`window` / `snapshot_interval`): each is a dump frame of every
/// particle.
inline constexpr double k_max_snapshots = 10000;

const DrumSettings& settings(const study::StudyConfig& config);
DrumSettings& settings(study::StudyConfig& config);

/// The drum's descriptor (registry.hpp lists it).
const Experiment& experiment();

/// The surface options the settings give.
postprocess::DrumSurfaceOptions surface_options(const DrumSettings& s);

// ---------------------------------------------------------------- the fill and the wall

/// The particle count of a study: the full-size count (`particles`, or bulk_volume × packing_fraction over the mean
/// particle volume of the size distribution) divided by K³ and rounded, at least 1.
long fill_count(const DrumSettings& s);
/// fill_count before rounding (it may exceed a long's range: a check compares it with k_max_particles first).
double exact_fill_count(const DrumSettings& s);

/// The sites of build_fill's lattice in the lowest planes of the drum that hold `wanted` of them; fewer (all the drum
/// holds) when the drum cannot. Never enumerates more than one plane beyond `wanted`.
long lattice_capacity(const DrumSettings& s, long wanted);

/// The full-size mean particle volume of the size distribution [m³]: Σ f_i π d_i³ / 6 over the classes, or the
/// truncated normal's third moment by quadrature.
double mean_particle_volume(const DrumSettings& s);

/// The fill: `fill_count` particles with radii from the size distribution × K, on a face-centred cubic lattice of
/// nearest-neighbour distance 2 r_max (1 + 2 %) inside the drum, lowest sites first, the radii shuffled over the sites
/// by a generator seeded with `seed`: identical for every sample of a study. Throws util::UserError when the drum
/// holds fewer sites than particles (the study file's check refuses such a fill first, at its line).
std::vector<Particle> build_fill(const DrumSettings& s, std::uint64_t seed);

/// The wall: a closed prism of `sides` sides about the y axis from y = 0 to y = depth, as one triangle mesh — the rim
/// (2 triangles a side) and two end plates, each a centre fan of sides/2 triangles inside a ring at R/2 stitched to
/// the rim's polygon (3 sides/2 triangles): 6·sides triangles. The polygon's vertices lie at R √(2π / (n sin(2π/n))),
/// so that its cross-section has the circle's area (the flat of a side then lies 0.07 % inside R for 48 sides).
/// Normals point into the drum.
std::vector<Triangle> drum_mesh(double radius, double depth, int sides);

/// The radius of the polygon's vertices (drum_mesh).
double polygon_vertex_radius(double radius, int sides);

// ---------------------------------------------------------------- a laboratory photograph

/// Where the drum is in a photograph, and how it turns: `demsa measure IMAGE` reads it from a small TOML file beside
/// the image (photograph_geometry_file).
struct PhotographSettings {
  double radius_m = 0.042;     ///< the drum's inner radius [m]
  bool spans_diameter = true;  ///< the square picture spans the inner diameter (the GranuDrum's images)
  double centre_col = 0.0;     ///< otherwise: the drum's centre [px], column from the left
  double centre_row = 0.0;     ///< row from the top
  double radius_px = 0.0;      ///< the inner radius [px]
  postprocess::DrumRotation rotation = postprocess::DrumRotation::clockwise;
  bool dark_material = true;  ///< the powder is darker than the empty drum
  postprocess::DrumSurfaceOptions
      surface;  ///< judged_radius, angle_half_width, stations (DrumSettings' by default), threshold
};

/// The geometry file of a photograph: IMAGE.drum.toml beside it when there is one, else drum.toml in its folder;
/// none when neither exists.
std::optional<std::filesystem::path> photograph_geometry_file(const std::filesystem::path& image);

/// Reads a photograph's geometry file. Keys (all optional but `radius` or the preset): `preset = "granudrum"`,
/// `radius` [m], `spans_diameter`, `centre_col`, `centre_row`, `radius_px`, `rotation`, `dark_material`,
/// `judged_radius`, `angle_half_width`, `stations`, `threshold`. Throws util::UserError "FILE:LINE: key = value: ..."
/// on an unknown key, a wrong type or a value out of range.
PhotographSettings read_photograph_settings(const std::filesystem::path& file);

/// What a photograph measures: the names and units of a case's observables (measure), and the surface.
struct PhotographMeasurement {
  std::map<std::string, double> values;    ///< in the stored units of describe()
  postprocess::DrumSurfaceResult surface;  ///< the surface and its band
  postprocess::DrumGeometry geometry;
};

/// Measures a laboratory photograph (BMP or PNG): postprocess::drum_image_from_photograph, then
/// measure_drum_surface, under the observable names of a simulated case.
PhotographMeasurement measure_photograph(const std::filesystem::path& image, const PhotographSettings& settings);

/// The observable values of a measured surface (the names and stored units of describe()).
std::map<std::string, double> observable_values(const postprocess::DrumSurfaceResult& r);

// ---------------------------------------------------------------- observables
inline constexpr std::string_view k_dynamic_angle = "dynamic_angle";  ///< [deg]
inline constexpr std::string_view k_surface_prefix = "surface_";      ///< surface_K: height at station K [m]
inline constexpr std::string_view k_s_shape = "s_shape";              ///< [m]
inline constexpr std::string_view k_fill_fraction = "fill_fraction";  ///< bed area / π R²
inline constexpr std::string_view k_angle_uncertainty = "dynamic_angle_uncertainty";  ///< recorded [deg]
inline constexpr std::string_view k_snapshots = "snapshots";                          ///< recorded: snapshots averaged

// ---------------------------------------------------------------- files of a drum case
inline constexpr const char* k_final_dump = "drum_final.dump";
inline constexpr const char* k_snapshots_dump = "drum_snapshots.dump";  ///< every snapshot_interval over the window
inline constexpr const char* k_mesh_file = "drum_wall.stl";
inline constexpr const char* k_occupancy_png = "occupancy.png";  ///< the measured side view
/// The side view with its measurement drawn (postprocess::drum_surface_overlay): the surface, its band, the angle's
/// line and the stations.
inline constexpr const char* k_surface_png = "occupancy_surface.png";

/// The atom-steps of a written case by its schedule (case.cpp): Experiment::case_cost.
CaseCost case_cost(const study::StudyConfig& config, const nlohmann::json& case_json, const std::filesystem::path& file,
                   const nlohmann::json& probed);

}  // namespace demsa::experiments::drum
