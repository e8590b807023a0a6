#!/usr/bin/python3
"""Writes scenes/maps/saddle.obj: an 8x8-quad saddle patch z = 0.3 (x^2 - y^2) over
[-0.5, 0.5]^2 with UVs (u along x, v along y), the OBJ-file example of the bundled scenes."""
import sys


def main(path):
    n = 8
    lines = ["# pgt example mesh: saddle patch, 8 x 8 quads, UVs over [0,1]^2"]
    for j in range(n + 1):
        for i in range(n + 1):
            x, y = i / n - 0.5, j / n - 0.5
            lines.append(f"v {x:.6f} {y:.6f} {0.3 * (x * x - y * y):.6f}")
    for j in range(n + 1):
        for i in range(n + 1):
            lines.append(f"vt {i / n:.6f} {j / n:.6f}")
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i + 1
            b, c, d = a + 1, a + n + 2, a + n + 1
            lines.append(f"f {a}/{a} {b}/{b} {c}/{c} {d}/{d}")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "scenes/maps/saddle.obj")
