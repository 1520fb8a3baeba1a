"""How a frame is cut into chunks: contiguous sample ranges, or a grid of tiles.

A chunk is a dict with `samples` (A, B) and `crop` (x0, y0, x1, y1) or None,
exactly what `pmc render --samples A:B [--crop x0,y0,x1,y1]` takes.
"""


def sample_ranges(spp, chunks):
    """[0, spp) cut into `chunks` contiguous ranges whose sizes differ by at most one."""
    if chunks < 1:
        raise ValueError("--chunks must be at least 1")
    if chunks > spp:
        raise ValueError(f"--chunks {chunks} is more than the frame's {spp} samples per pixel")
    base, extra = divmod(spp, chunks)
    out, a = [], 0
    for k in range(chunks):
        b = a + base + (1 if k < extra else 0)
        out.append((a, b))
        a = b
    return out


def tile_grid(width, height, chunks):
    """The frame cut into `chunks` tiles: a grid of gx columns by gy rows
    (gx * gy == chunks, as square as the factors allow), edges spread evenly."""
    if chunks < 1:
        raise ValueError("--chunks must be at least 1")
    gy = max(d for d in range(1, int(chunks ** 0.5) + 1) if chunks % d == 0)
    gx = chunks // gy
    if width < height:
        gx, gy = gy, gx
    if gx > width or gy > height:
        raise ValueError(f"--chunks {chunks}: a {gx}x{gy} tile grid does not fit a {width}x{height} image")
    xs = [width * i // gx for i in range(gx + 1)]
    ys = [height * j // gy for j in range(gy + 1)]
    return [(xs[i], ys[j], xs[i + 1], ys[j + 1]) for j in range(gy) for i in range(gx)]


def make_chunks(split, chunks, spp, width, height):
    if split == "samples":
        return [{"samples": r, "crop": None} for r in sample_ranges(spp, chunks)]
    if split == "tiles":
        return [{"samples": (0, spp), "crop": t} for t in tile_grid(width, height, chunks)]
    raise ValueError(f"--split must be samples or tiles, got {split!r}")
