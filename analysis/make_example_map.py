#!/usr/bin/python3
"""Writes scenes/maps/stones.png: a 128x128 16-bit height map of rounded cobblestones
(seeded Voronoi cells with domed tops), the file-based example map of the bundled scenes.
Run with Debian's /usr/bin/python3 (numpy, python3-openimageio)."""
import sys

import numpy as np
import OpenImageIO as oiio


def stones(size=128, cells=6, seed=4):
    rng = np.random.default_rng(seed)
    pts = rng.random((cells * cells, 2))
    # Tile the feature points 3x3 so that the map repeats seamlessly.
    tiles = np.concatenate([pts + [dx, dy] for dx in (-1, 0, 1) for dy in (-1, 0, 1)])
    c = (np.arange(size) + 0.5) / size
    u, v = np.meshgrid(c, c)
    d = np.sqrt((u[..., None] - tiles[:, 0]) ** 2 + (v[..., None] - tiles[:, 1]) ** 2)
    d.sort(axis=-1)
    edge = (d[..., 1] - d[..., 0]) * cells  # 0 on cell borders, grows inside
    return np.clip(np.sqrt(np.clip(edge / 0.6, 0, 1)), 0, 1)


def main(path):
    h = stones()
    # Image rows run top-down; row 0 of `h` is v = 0 (bottom), so flip for the file.
    pixels = np.flipud(h)
    out = oiio.ImageOutput.create(path)
    spec = oiio.ImageSpec(pixels.shape[1], pixels.shape[0], 1, "uint16")
    out.open(path, spec)
    data = np.round(pixels * 65535).astype(np.uint16).reshape(pixels.shape[0], pixels.shape[1], 1)
    out.write_image(np.ascontiguousarray(data))
    out.close()


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "scenes/maps/stones.png")
