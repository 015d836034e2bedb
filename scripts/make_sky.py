#!/usr/bin/env python3
"""Writes the project's own environment map, scenes/dusk_sky.hdr (docs/local-environment.md,
docs/scenes.md): a 1024 x 512 lat-long map (docs/environment.md convention: u = frac(atan2(x, -z) /
2 pi), v = acos(y) / pi, row 0 at the top) of a dusk sky, generated here so the shipped scenes need
no downloaded asset. Radiance HDR (RGBE) with run-length encoded scanlines (the sky varies little
along a row, so 1024 x 512 stays small). The renderer reads the map piecewise constant (one value
per texel, as its estimators and the reference assume), so the resolution is what keeps the
horizon's steep gradient free of visible steps: 128 x 64 texels were 2.8 degrees each, 20 pixels of
the 640 x 360 scenes/materials.json view; 1024 x 512 are 0.35 degrees, under 3 pixels, and
neighbouring rows differ by under 4 %. Usage: scripts/make_sky.py [OUT]."""
import math
import struct
import sys

W, H = 1024, 512


def sky(x, y, z):
    """Linear RGB radiance towards direction (x, y, z), +y up."""
    if y < 0.0:  # ground: dark, slightly warm, brighter towards the horizon
        g = 0.03 + 0.05 * math.exp(8.0 * y)
        return (g * 1.1, g, g * 0.85)
    horizon = math.exp(-6.0 * y)  # warm glow near the horizon, deep blue above
    r = 0.08 + 0.55 * horizon
    g = 0.12 + 0.35 * horizon
    b = 0.30 + 0.15 * horizon
    # a low sun towards -x, +z (radius ~3 degrees) with a soft halo
    sx, sy, sz = -0.8, 0.12, 0.58
    n = math.sqrt(sx * sx + sy * sy + sz * sz)
    c = (x * sx + y * sy + z * sz) / n
    if c > math.cos(math.radians(3.0)):
        return (60.0, 42.0, 25.0)
    halo = 1.5 * math.exp(40.0 * (c - 1.0))
    return (r + halo, g + 0.7 * halo, b + 0.4 * halo)


def rgbe(r, g, b):
    m = max(r, g, b)
    if m < 1e-32:
        return bytes((0, 0, 0, 0))
    mant, e = math.frexp(m)
    f = mant * 256.0 / m
    return bytes((int(r * f), int(g * f), int(b * f), e + 128))


def rle_component(values):
    """New-style Radiance run-length encoding of one component of a scanline."""
    out = bytearray()
    i, n = 0, len(values)
    while i < n:
        run = 1
        while i + run < n and run < 127 and values[i + run] == values[i]:
            run += 1
        if run >= 4:
            out += bytes((128 + run, values[i]))
            i += run
            continue
        j = i  # a literal up to the next run of 4 or more (at most 128 bytes)
        while j < n and j - i < 128:
            if j + 3 < n and values[j] == values[j + 1] == values[j + 2] == values[j + 3]:
                break
            j += 1
        out += bytes((j - i,)) + bytes(values[i:j])
        i = j
    return out


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "scenes/dusk_sky.hdr"
    data = bytearray(b"#?RADIANCE\n# nearfield scripts/make_sky.py: generated dusk sky\nFORMAT=32-bit_rle_rgbe\n\n")
    data += f"-Y {H} +X {W}\n".encode()
    for row in range(H):
        v = (row + 0.5) / H
        line = []
        for a in range(W):
            u = (a + 0.5) / W
            phi, theta = 2.0 * math.pi * u, math.pi * v
            # inverse of u = atan2(x, -z) / 2 pi, v = acos(y) / pi
            x, y, z = math.sin(theta) * math.sin(phi), math.cos(theta), -math.sin(theta) * math.cos(phi)
            line.append(rgbe(*sky(x, y, z)))
        data += bytes((2, 2, W >> 8, W & 255))
        for c in range(4):
            data += rle_component([p[c] for p in line])
    with open(out, "wb") as f:
        f.write(data)


if __name__ == "__main__":
    main()
