# Ishigami's function (a = 7, b = 0.1) at every row of design.csv, written to y.csv in the same order.
import csv, math
with open("design.csv") as f, open("y.csv", "w") as out:
    out.write("y\n")
    for row in csv.DictReader(f):
        x1, x2, x3 = (float(row[k]) for k in ("x1", "x2", "x3"))
        out.write(f"{math.sin(x1) + 7 * math.sin(x2) ** 2 + 0.1 * x3 ** 4 * math.sin(x1)!r}\n")
