#!/usr/bin/python3
"""Writes the OBJ examples of the bundled scenes:
scenes/maps/saddle.obj: an 8x8-quad saddle patch z = 0.3 (x^2 - y^2) over [-0.5, 0.5]^2 with
UVs (u along x, v along y);
scenes/maps/mirrored.obj: a flat 8x4-quad strip whose right half reuses the left half's
texture mirrored (u = 1 - x'), as symmetric assets do: Listing 7.4 gives w = -1 there, and the
vertices on the mirror line average opposite tangents."""
import sys


def write_grid(path, comment, nx, ny, position, uv):
    """A (nx x ny)-quad grid; position(i, j) -> "x y z" text, uv(i, j) -> "u v" text, with
    one texture coordinate per vertex (same index)."""
    lines = [f"# pgt example mesh: {comment}"]
    lines += [f"v {position(i, j)}" for j in range(ny + 1) for i in range(nx + 1)]
    lines += [f"vt {uv(i, j)}" for j in range(ny + 1) for i in range(nx + 1)]
    for j in range(ny):
        for i in range(nx):
            a = j * (nx + 1) + i + 1
            b, c, d = a + 1, a + nx + 2, a + nx + 1
            lines.append(f"f {a}/{a} {b}/{b} {c}/{c} {d}/{d}")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def saddle(path):
    n = 8

    def position(i, j):
        x, y = i / n - 0.5, j / n - 0.5
        return f"{x:.6f} {y:.6f} {0.3 * (x * x - y * y):.6f}"

    write_grid(path, "saddle patch, 8 x 8 quads, UVs over [0,1]^2", n, n, position,
               lambda i, j: f"{i / n:.6f} {j / n:.6f}")


def mirrored(path):
    nx, ny, half = 8, 4, 4

    def uv(i, j):
        u = i / half if i <= half else (nx - i) / half  # 0 -> 1 -> 0
        return f"{u:.6f} {j / ny:.6f}"

    write_grid(path, "flat strip, right half mirrored in u", nx, ny,
               lambda i, j: f"{i / nx - 0.5:.6f} {(j / ny - 0.5) * 0.5:.6f} 0", uv)


if __name__ == "__main__":
    folder = sys.argv[1] if len(sys.argv) > 1 else "scenes/maps"
    saddle(f"{folder}/saddle.obj")
    mirrored(f"{folder}/mirrored.obj")
