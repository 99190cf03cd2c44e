"""The fake LIGGGHTS's oedometer: plate_states.txt with settlements that grow as E falls, and a lattice of spheres as its
final dump (tests/integration/fake_liggghts/liggghts loads this file by the case's experiment
name and calls run())."""
from fake_common import first_two

def run(case, unit, mode, particles, sample):
    """Writes the case's outputs; returns (final dump name, rows) for the fake's main to write, or None when the
    final dump is written here."""
    u0, u1 = first_two(unit)
    loads = case.get("oedometer", {}).get("loads_N", [100, 400, 1100, 2700])
    stiffness = 1.0 + 4.0 * u0 + 0.5 * u1
    with open("plate_states.txt", "w") as f:
        f.write("# load_N plate_z_m force_N converged\n")
        for i, load in enumerate(loads):
            converged = 0 if (mode == "plate" and i == len(loads) - 1) else 1
            z = 0.1 - 1e-5 * load / stiffness
            f.write(f"{load} {z:.12g} {load if converged else 0.8 * load} {converged}\n")
    rows = [(0.01 * (i % 9) - 0.04, 0.01 * ((i // 9) % 9) - 0.04, 0.003 + 0.006 * (i // 81), 0.003)
            for i in range(particles)]
    return "oedometer_final.dump", rows
