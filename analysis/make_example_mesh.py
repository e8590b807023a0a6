#!/usr/bin/python3
"""Writes the OBJ examples of the bundled scenes:
scenes/maps/saddle.obj: an 8x8-quad saddle patch z = 0.3 (x^2 - y^2) over [-0.5, 0.5]^2 with
UVs (u along x, v along y);
scenes/maps/mirrored.obj: a flat 8x4-quad strip whose right half reuses the left half's
texture mirrored (u = 1 - x'), as symmetric assets do: Listing 7.4 gives w = -1 there, and the
vertices on the mirror line average opposite tangents."""
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


def mirrored(path):
    nx, ny = 8, 4
    lines = ["# pgt example mesh: flat strip, right half mirrored in u"]
    for j in range(ny + 1):
        for i in range(nx + 1):
            lines.append(f"v {i / nx - 0.5:.6f} {(j / ny - 0.5) * 0.5:.6f} 0")
    half = nx // 2
    for j in range(ny + 1):
        for i in range(nx + 1):
            u = i / half if i <= half else (nx - i) / half  # 0 -> 1 -> 0
            lines.append(f"vt {u:.6f} {j / ny:.6f}")
    for j in range(ny):
        for i in range(nx):
            a = j * (nx + 1) + i + 1
            b, c, d = a + 1, a + nx + 2, a + nx + 1
            lines.append(f"f {a}/{a} {b}/{b} {c}/{c} {d}/{d}")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    folder = sys.argv[1] if len(sys.argv) > 1 else "scenes/maps"
    main(f"{folder}/saddle.obj")
    mirrored(f"{folder}/mirrored.obj")
