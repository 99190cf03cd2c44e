"""The fake LIGGGHTS's draw-down: the material left in the box and its discharge, set by the sample's first two unit-cube
coordinates (tests/integration/fake_liggghts/liggghts loads this file by the case's experiment
name and calls run())."""
import math

from fake_common import dump_text, first_two

def write_drawdown(case, u0, u1):
    """A draw-down: the material left in the box under a surface rising from each slot edge at 25 + 15 u0 degrees,
    discharged at 0.2 + 0.2 u1 kg/s for half a second."""
    s = case["drawdown"]
    half, slot, depth, skip = s["width_m"] / 2, s["slot_width_m"] / 2, s["depth_m"], s["floor_particles"]
    angle = math.radians(25 + 15 * u0)
    r = 0.002
    rows = [(-half + 0.002 * i, 0.01, r, r) for i in range(skip)]  # the floor layer: ids 1..skip
    x = -half + r
    while x <= half - r:
        edge = abs(x) - slot
        if edge >= 0:
            top = 0.004 + edge * math.tan(angle)
            y = r
            while y < depth:
                z = 0.006
                while z + r <= top:
                    rows.append((x, y, z, r))
                    z += 2 * r
                rows.append((x, y, top - r, r))
                y += 2 * r
        x += 2 * r
    open("drawdown_final.dump", "w").write(dump_text(rows))
    rate = 0.2 + 0.2 * u1
    with open("drawdown_discharge.txt", "w") as f:
        f.write("# t_open_s discharged_kg atoms\n")
        for k in range(101):
            t = 0.01 * k
            f.write(f"{t} {rate * min(t, 0.5)} {len(rows)}\n")
    fill = rate * 0.5 * 1.25
    open("drawdown_end.txt", "w").write(f"stopped 1\nt_open 1\nfill_mass {fill}\ndischarged {rate * 0.5}\n"
                                        f"removed {case['assembly']['particles'] + skip - len(rows)}\n")


def run(case, unit, mode, particles, sample):
    """Writes the case's outputs; returns (final dump name, rows) for the fake's main to write, or None when the
    final dump is written here."""
    u0, u1 = first_two(unit)
    write_drawdown(case, u0, u1)
    return None
