"""What the per-experiment fakes of LIGGGHTS (orchestrator/experiments/NAME/fake_liggghts.py) share with the fake's
main (tests/integration/fake_liggghts/liggghts): the text of a LIGGGHTS dump and the first two unit-cube coordinates."""


def dump_text(rows):
    lines = ["ITEM: TIMESTEP", "300000", "ITEM: NUMBER OF ATOMS", str(len(rows)), "ITEM: BOX BOUNDS ff ff ff",
             "-0.15 0.15", "-0.15 0.15", "0 0.3", "ITEM: ATOMS id type x y z radius vx vy vz"]
    for i, (x, y, z, r) in enumerate(rows):
        lines.append(f"{i + 1} 1 {x:.9g} {y:.9g} {z:.9g} {r:.6g} 0 0 0")
    return "\n".join(lines) + "\n"


def first_two(unit):
    """The sample's first two unit-cube coordinates (0.5 for a missing one)."""
    return (unit[0] if len(unit) > 0 else 0.5), (unit[1] if len(unit) > 1 else 0.5)
