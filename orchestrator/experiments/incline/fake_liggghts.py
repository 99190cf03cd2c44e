"""The fake LIGGGHTS's tilting incline: probes that start rolling and sliding at tilts set by the sample's first two
unit-cube coordinates (tests/integration/fake_liggghts/liggghts loads this file by the case's experiment
name and calls run())."""
import math

from fake_common import dump_text, first_two

def incline_position(tilt, onset, k, rate):
    """Down-slope distance of a probe started from rest at `onset` on a plate tilting at `rate` (postprocess/incline.hpp's
    start: x = k g sqrt(1 + mu^2) Omega t^3 / 6)."""
    if tilt <= onset:
        return 0.0
    mu = math.tan(math.radians(onset))
    t = (tilt - onset) / rate
    return k * 9.81 * math.sqrt(1 + mu * mu) * math.radians(rate) * t ** 3 / 6


def write_incline(case, u0, u1, mode):
    """An incline: its free probes start at 5 + 20 u0 degrees, its locked ones at 20 + 30 u1; incline_probes.dump every
    record_steps from the tilt's start, incline_end.txt, and the final dump (every probe removed)."""
    s = case["incline"]
    rolling, sliding = s["rolling_probes"], s["sliding_probes"]
    rate, start, every, dt = s["tilt_rate_deg_s"], s["tilt_start_step"], s["record_steps"], case["dt"]
    roll_onset, slide_onset = 5 + 20 * u0, 20 + 30 * u1
    frames = []
    k = 0
    while True:
        step = start + k * every
        tilt = rate * (step - start) * dt
        if tilt > 60:
            break
        rows = []
        for i in range(rolling + sliding):
            onset, factor = (roll_onset, 5 / 7) if i < rolling else (slide_onset, 1.0)
            x = incline_position(tilt, onset, factor, rate)
            if x < s["stop_distance_m"]:
                rows.append((i + 1, x))
        frames.append((step, rows))
        k += 1
    with open("incline_probes.dump", "w") as f:
        for step, rows in frames:
            f.write(f"ITEM: TIMESTEP\n{step}\nITEM: NUMBER OF ATOMS\n{len(rows)}\nITEM: BOX BOUNDS ff ff ff\n"
                    "-0.02 0.7\n-0.1 0.1\n-0.002 0.05\nITEM: ATOMS id type x y z radius vx vy vz\n")
            for aid, x in rows:
                f.write(f"{aid} 1 {x:.12g} 0 0.002 0.002 0 0 0\n")
    open("incline_end.txt", "w").write(f"end_tilt 60\nremoved {rolling + sliding}\n")
    open("incline_final.dump", "w").write(dump_text([]) if mode != "truncated" else "ITEM: TIMESTEP\n")


def run(case, unit, mode, particles, sample):
    """Writes the case's outputs; returns (final dump name, rows) for the fake's main to write, or None when the
    final dump is written here."""
    u0, u1 = first_two(unit)
    write_incline(case, u0, u1, mode)
    return None
