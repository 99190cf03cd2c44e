#include "postprocess/incline.hpp"

#include "postprocess/error.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <stdexcept>

namespace demsa::postprocess {

namespace {

constexpr double k_deg = std::numbers::pi / 180.0;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// Linear interpolation of y at x between (x0, y0) and (x1, y1).
double between(double x, double x0, double y0, double x1, double y1) {
  return x1 == x0 ? y1 : y0 + (y1 - y0) * (x - x0) / (x1 - x0);
}

}  // namespace

void InclineOptions::validate() const {
  const auto positive = [](double v, const char* name) {
    if (!(v > 0) || !std::isfinite(v)) throw std::invalid_argument(fmt::format("{} = {}: must be > 0", name, v));
  };
  positive(tilt_rate, "tilt_rate");
  positive(dt, "dt");
  positive(gravity, "gravity");
  positive(onset_distance, "onset_distance");
  if (!(speed_angle >= 0 && speed_angle < 90))
    throw std::invalid_argument(fmt::format("speed_angle = {}: must lie in [0, 90)", speed_angle));
  if (rolling_probes < 0) throw std::invalid_argument(fmt::format("rolling_probes = {}: must be >= 0", rolling_probes));
  if (!(max_tilt > 0 && max_tilt <= 90))
    throw std::invalid_argument(fmt::format("max_tilt = {}: must lie in (0, 90]", max_tilt));
}

double incline_onset(double measured, double distance, double k, double tilt_rate, double gravity) {
  // x = k g sqrt(1 + mu^2) Omega t^3 / 6 with mu = tan(theta_c), theta_c = measured - Omega t (header comment). The
  // lag is a few tenths of a degree to a degree: the iteration converges in a few steps.
  const double omega = tilt_rate * k_deg;  // rad/s
  double onset = measured;
  for (int i = 0; i < 50; ++i) {
    const double mu = std::tan(std::clamp(onset, 0.0, 89.0) * k_deg);
    const double t = std::cbrt(6.0 * distance / (k * gravity * std::sqrt(1.0 + mu * mu) * omega));
    const double next = measured - tilt_rate * t;
    if (std::abs(next - onset) < 1e-9) return next;
    onset = next;
  }
  return onset;
}

InclineResult measure_incline(const std::filesystem::path& dump, const InclineOptions& options) {
  options.validate();
  DumpReaderOptions reader_options;
  reader_options.required_columns = {"id", "x"};
  DumpReader reader(dump, reader_options);
  std::map<long, InclineProbe> probes;
  std::map<long, double> first_x;
  std::map<long, std::pair<double, double>> previous_speed;  // id -> (tilt, vx) of its last frame below speed_angle
  InclineResult result;
  DumpFrame frame;
  while (reader.next(frame)) {
    const double tilt = options.tilt_rate * static_cast<double>(frame.timestep - options.tilt_start_step) * options.dt;
    // A tilt beyond 90° turns the plate over: the frame's time step is not of the schedule the options describe.
    if (tilt > 90.0)
      throw InputError(fmt::format(
          "{}: the frame of time step {} lies at a tilt of {:.6g}° (tilt_rate {} deg/s from step {}, dt {} s), beyond "
          "90°: the dump does not follow its case's schedule",
          dump.string(), frame.timestep, tilt, options.tilt_rate, options.tilt_start_step, options.dt));
    result.last_tilt = tilt;
    check_unique_ids(frame);
    const std::span<const double> ids = frame.column("id");
    const std::span<const double> x = frame.column("x");
    const bool has_vx = frame.has_column("vx");
    for (std::size_t i = 0; i < ids.size(); ++i) {
      const long id = std::lround(ids[i]);
      InclineProbe& p = probes[id];
      if (p.tilt.empty()) {
        p.id = id;
        p.rolling = id <= options.rolling_probes;
        first_x[id] = x[i];
      }
      const double moved = x[i] - first_x[id];
      if (!p.onset_raw && moved >= options.onset_distance && !p.tilt.empty())
        p.onset_raw = between(options.onset_distance, p.displacement.back(), p.tilt.back(), moved, tilt);
      p.tilt.push_back(tilt);
      p.displacement.push_back(moved);
      if (p.rolling && has_vx && !p.speed) {
        const double vx = frame.column("vx")[i];
        if (tilt >= options.speed_angle) {
          const auto it = previous_speed.find(id);
          p.speed = it == previous_speed.end()
                        ? vx
                        : between(options.speed_angle, it->second.first, it->second.second, tilt, vx);
        } else {
          previous_speed[id] = {tilt, vx};
        }
      }
    }
  }
  std::vector<double> roll, slide, speed;
  for (auto& [id, p] : probes) {
    (p.rolling ? result.rolling_probes : result.sliding_probes) += 1;
    // The schedule records past max_tilt up to one record; an onset found there lies beyond the tilt the case
    // applied and is none.
    if (p.onset_raw && *p.onset_raw > options.max_tilt) p.onset_raw.reset();
    if (p.onset_raw) {
      p.onset = incline_onset(*p.onset_raw, options.onset_distance, p.rolling ? 5.0 / 7.0 : 1.0, options.tilt_rate,
                              options.gravity);
      (p.rolling ? roll : slide).push_back(*p.onset);
    }
    if (p.speed) speed.push_back(*p.speed);
    result.probes.push_back(std::move(p));
  }
  result.rolled = static_cast<int>(roll.size());
  result.slid = static_cast<int>(slide.size());
  result.with_speed = static_cast<int>(speed.size());
  // A median only when most probes of the kind give a value (a median of the few that moved would be biased low).
  if (result.rolling_probes > 0 && 2 * result.rolled > result.rolling_probes) result.roll_angle = median(roll);
  if (result.sliding_probes > 0 && 2 * result.slid > result.sliding_probes) result.slide_angle = median(slide);
  if (result.rolling_probes > 0 && 2 * result.with_speed > result.rolling_probes) result.roll_speed = median(speed);
  return result;
}

}  // namespace demsa::postprocess
