#pragma once
// What an experiment shows of one case in the report (Experiment::case_report): tables, and figures as plain data
// (numbers and labels) that report/plot.hpp draws. A figure kind may serve several experiments; the report draws
// whatever kind an experiment hands it and knows no experiment.
#include <string>
#include <variant>
#include <vector>

namespace demsa::experiments {

/// A table of the report: a caption, a header and rows as long as it.
struct CaseTable {
  std::string caption;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;  ///< each as long as the header
};

/// A particle of the measured pile, with the direction in which it is a boundary particle (paper §3.3, Fig. 4a).
struct PileParticle {
  double x = 0, y = 0, z = 0;  ///< centre [m]
  double radius = 0;           ///< [m]
  int direction = -1;          ///< i_φ when it is a boundary particle, -1 otherwise
};
/// The line fitted in one direction, as a segment in that direction's vertical half-plane.
struct PileLine {
  int direction = 0;                          ///< i_φ
  double phi_deg = 0;                         ///< φ of the direction [°] (paper eq. 9: e = (cos φ, −sin φ))
  double angle_deg = 0;                       ///< slope angle of the line [°]
  double rho0 = 0, z0 = 0, rho1 = 0, z1 = 0;  ///< segment ends: radial distance and height [m]
};
/// The pile seen from the side (paper Fig. 4): a cross section with its boundary particles and fitted lines,
/// and every direction's boundary particles and lines unrolled onto one radial plane.
struct PileSideView {
  std::string title;
  std::vector<PileParticle> particles;  ///< the filtered pile
  std::vector<PileLine> lines;          ///< one per direction that has a line
  int directions = 180;                 ///< φ_N
  double angle_deg = 0;                 ///< the mean angle of repose [°]
  double height = 0;                    ///< h_P [m]
  double pedestal_radius = 0.05;        ///< [m]
  double pedestal_height = 0.005;       ///< [m]
  double slab = 0;                      ///< half-thickness of the cross section [m]; 0: 2 × largest radius
};
/// Settlement against stress for the load steps (paper Fig. 5); settlements relative to the first load.
struct SettlementCurve {
  std::string title;
  std::vector<double> loads;          ///< L_n [N]
  double area = 0.01;                 ///< loaded area [m²] (stress = load / area)
  std::vector<double> simulated;      ///< s_n [m] per load (first = 0); empty when not simulated
  std::vector<double> measured;       ///< s̃_n [m] per load (first = 0); empty when not measured
  std::vector<double> measured_low;   ///< lowest measured s̃_n [m]; empty = no error bars
  std::vector<double> measured_high;  ///< highest measured s̃_n [m]
};
/// The force on the plate over the iteration (paper Fig. 6b), with the load steps and the plate height.
struct PlateHistoryPlot {
  std::string title;
  std::vector<double> step;     ///< time step of each row
  std::vector<double> load;     ///< load step L_n being applied [N]
  std::vector<double> force;    ///< particle force on the plate [N]
  std::vector<double> plate_z;  ///< plate height [m]
};
/// Curves of y against x (an incline's probe displacements against the tilt, a draw-down's discharged mass against
/// time): one line per series, with an optional horizontal reference line.
struct LinePlot {
  struct Series {
    std::string name;  ///< legend entry ("" keeps it out of the legend)
    std::vector<double> x, y;
    std::string colour;   ///< "#rrggbb"; "" picks one
    bool points = false;  ///< a cloud of points instead of a line
  };
  std::string title;
  std::string x_label;
  std::string y_label;
  std::vector<Series> series;
  double y_reference = 0.0;  ///< a dashed horizontal line at this y when y_reference_label is not empty
  std::string y_reference_label;
};

/// A picture the experiment wrote itself (a drum's time-averaged side view): the report copies the PNG beside its
/// plots.
struct ImageFigure {
  std::string png;  ///< path of the PNG file
};

/// The data of one figure of a case.
using CaseFigureData = std::variant<PileSideView, SettlementCurve, PlateHistoryPlot, LinePlot, ImageFigure>;

}  // namespace demsa::experiments
