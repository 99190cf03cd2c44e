"""The fake LIGGGHTS's rotating drum: snapshots of a bed under a straight surface whose angle is set by the sample's
first unit-cube coordinate (tests/integration/fake_liggghts/liggghts loads this file by the case's experiment name and
calls run())."""
import math

from fake_common import dump_text, first_two


def write_drum(case, particles, u0):
    """drum_snapshots.dump holds three snapshots of a bed of overlapping discs (radius 1 mm, 0.5 mm apart, so that the
    bed's side view is solid) whose tops lie on the straight surface z = -5 mm -+ tan(a) x through the drum,
    a = 25 + 20 u0 degrees, high on the side the rotation carries the powder up (left for clockwise); the grid shifts
    by a fraction of its pitch between snapshots. drum_final.dump holds `particles` spheres."""
    s = case["drum"]
    radius, depth = s["radius_m"], s["depth_m"]
    angle = math.radians(25 + 20 * u0)
    sign = -1.0 if s["rotation"] == "clockwise" else 1.0
    r, pitch = 0.001, 0.0005
    lines = []
    for k, shift in enumerate((0.0, 0.33, 0.67)):
        rows = []
        n = int(radius / pitch) + 2
        for i in range(-n, n + 1):
            x = (i + shift) * pitch
            for j in range(-n, n + 1):
                z = (j + shift) * pitch
                if x * x + z * z > (radius - r) ** 2 or z > -0.005 + sign * math.tan(angle) * x - r:
                    continue
                rows.append((x, depth / 2, z))
        lines += ["ITEM: TIMESTEP", str(100000 + 100 * k), "ITEM: NUMBER OF ATOMS", str(len(rows)),
                  "ITEM: BOX BOUNDS ff ff ff", f"{-radius} {radius}", f"0 {depth}", f"{-radius} {radius}",
                  "ITEM: ATOMS id type x y z radius"]
        lines += [f"{i + 1} 1 {x:.9g} {y:.9g} {z:.9g} {r}" for i, (x, y, z) in enumerate(rows)]
    open("drum_snapshots.dump", "w").write("\n".join(lines) + "\n")
    open("drum_final.dump", "w").write(dump_text([(0.001 * (i % 40) - 0.02, depth / 2, -0.03 + 0.001 * (i // 40),
                                                    0.0005) for i in range(particles)]))


def run(case, unit, mode, particles, sample):
    """Writes the case's outputs, its final dump too; returns None."""
    u0, _ = first_two(unit)
    write_drum(case, particles, u0)
    return None
