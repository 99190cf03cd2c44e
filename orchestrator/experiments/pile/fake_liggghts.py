"""The fake LIGGGHTS's pile: a cone of spheres on the pedestal whose angle grows with the sample's first two unit-cube
coordinates (rings of spheres on its flank, the other particles on the ground around it) (tests/integration/fake_liggghts/liggghts loads this file by the case's experiment
name and calls run())."""
import math
import os
import random

from fake_common import dump_text, first_two

def cone(particles, angle_deg, rng):
    """Rings of spheres on the flank of a cone standing on the pedestal (base radius 0.045 m, top z = 0.005 m), one
    ring every particle diameter along the slant, so that every direction and level sees the flank; the particles
    left over lie on the ground around the pedestal (rolled off)."""
    base, top = 0.045, 0.005
    alpha = math.radians(angle_deg)
    slant = base / math.cos(alpha)
    r = math.sqrt(math.pi * base * slant / (4 * 0.9 * particles))
    rows = []
    k = 0
    while (k + 0.5) * 2 * r < slant:
        s = (k + 0.5) * 2 * r
        rho = base - s * math.cos(alpha)
        z = top + s * math.sin(alpha) + r * math.cos(alpha)
        n = max(1, int(2 * math.pi * rho / (2 * r)))
        shift = rng.uniform(0, 2 * math.pi)
        for m in range(n):
            phi = shift + 2 * math.pi * m / n
            # the centre sits one radius inside the flank
            rc = rho - r * math.sin(alpha)
            rows.append((rc * math.cos(phi), rc * math.sin(phi), z, r))
        k += 1
    rows = rows[:particles]
    for m in range(particles - len(rows)):
        phi = 2 * math.pi * m / max(1, particles - len(rows))
        rows.append((0.08 * math.cos(phi), 0.08 * math.sin(phi), r, r))
    return rows


def write_pile_history(case, particles, angle, drift, sample):
    """pile_settling.txt of a pile that settled for its whole cap, and the snapshots of its settling: a cone of
    angle + drift (t - t_end) at each listed check (t = check x check_steps x dt)."""
    pile, history = case["pile"], case["pile"]["history"]
    check_steps, dt = history["check_steps"], case["dt"]
    checks = -(-pile["settle_steps"] // check_steps)
    start = 100000
    end = start + checks * check_steps
    t_end = checks * check_steps * dt
    for k in history["snapshot_checks"]:
        t = k * check_steps * dt
        rows = cone(particles, angle + drift * (t - t_end), random.Random(sample))
        open(f"pile_snapshot_{k}.dump", "w").write(dump_text(rows))
    criterion = 1 if pile["settle_window_checks"] > 0 else 0
    open("pile_settling.txt", "w").write(
        f"criterion {criterion}\nsettled {criterion}\nend_step {end}\nfastest_on_pedestal 0.001\n"
        f"speed_limit 0.002\non_pedestal {particles}\nfast_on_pedestal 0\nremoved 0\nstart_step {start}\n"
        f"check_steps {check_steps}\n")


def run(case, unit, mode, particles, sample):
    """Writes the case's outputs; returns (final dump name, rows) for the fake's main to write, or None when the
    final dump is written here."""
    u0, u1 = first_two(unit)
    angle = 24.0 + 12.0 * u0 + 6.0 * u1 * u1
    noise_sd = float(os.environ.get("FAKE_LIGGGHTS_NOISE", "0"))
    if noise_sd > 0:
        assembly_seed = case.get("replicate", {}).get("assembly_seed", case.get("seed", 0))
        angle += noise_sd * random.Random(f"{assembly_seed}/{unit}").gauss(0.0, 1.0)
    drift = os.environ.get("FAKE_LIGGGHTS_DRIFT")
    if drift is not None and "history" in case.get("pile", {}):
        write_pile_history(case, particles, angle, float(drift), sample)
    rows = cone(particles, angle, random.Random(sample))
    if mode == "offpedestal":
        rows = [(0.09, 0.0, 0.002 * (i + 1), 0.002) for i in range(particles)]
    return "pile_final.dump", rows
